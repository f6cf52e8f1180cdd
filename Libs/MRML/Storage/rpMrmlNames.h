#pragma once
// The names our MRML reader and writer share (one place): the MRML attributes that carry fields
// Slicer has no place for ("RoboPlan.<field>", "RoboPlan.Class"), the display and storage node
// tags read with the node they serve, and the layout codes of vtkMRMLLayoutNode.
#include <string>
#include <vector>

namespace rp {

/// Our fields travel as MRML node attributes "RoboPlan.<field>" (e.g. RoboPlan.tissueClass,
/// RoboPlan.haptic); "RoboPlan.Class" names our node class when it is a subclass of the one the
/// MRML tag maps to (e.g. a tracked tool written as a LinearTransform).
constexpr const char* MrmlOwnPrefix = "RoboPlan.";
constexpr const char* MrmlOwnClassAttribute = "RoboPlan.Class";
/// Our node attribute that marks a scalar volume read from a Slicer label map volume, so that it
/// is written back as one (LabelMapVolume); not itself written to MRML.
constexpr const char* MrmlLabelMapAttribute = "Slicer.LabelMapVolume";

/// Display and storage node tags of the node types we read (they are read with their node).
bool IsMrmlHelperTag(const std::string& tag);

/// Links between plan nodes that travel in the MRML `references` (Slicer keeps every role):
/// a screw's model ("screwModel").
const std::vector<const char*>& MrmlPlanReferenceRoles();

/// vtkMRMLLayoutNode's view arrangement code <-> vtkRPLayoutNode::Arrangement.
int ArrangementFromSlicerLayout(int slicerLayout);
int SlicerLayoutFromArrangement(int arrangement);

}  // namespace rp
