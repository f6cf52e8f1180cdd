#include "rpMrmlNames.h"

#include <set>

#include "vtkRPLayoutNode.h"
#include "vtkRPScrewNode.h"

namespace rp {

bool IsMrmlHelperTag(const std::string& tag) {
  static const std::set<std::string> tags = {
      "VolumeDisplay",       "LabelMapVolumeDisplay", "ScalarVolumeDisplay",   "VolumeArchetypeStorage",
      "ModelDisplay",        "ModelStorage",          "TransformStorage",      "SegmentationStorage",
      "SegmentationDisplay", "MarkupsJsonStorage",    "MarkupsFiducialStorage", "MarkupsFiducialDisplay",
      "MarkupsDisplay",      "MarkupsPlaneDisplay",   "MarkupsPlaneJsonStorage", "SliceComposite"};
  return tags.count(tag) > 0;
}

const std::vector<const char*>& MrmlPlanReferenceRoles() {
  static const std::vector<const char*> roles = {vtkRPScrewNode::ScrewModelRole()};
  return roles;
}

// Slicer's codes (vtkMRMLLayoutNode::SlicerLayout...View): 3 four-up, 4 3D only, 6/7/8 the red,
// yellow, green slice alone; the default and conventional layouts (1, 2) are shown four-up here.
int ArrangementFromSlicerLayout(int slicerLayout) {
  switch (slicerLayout) {
    case 4: return vtkRPLayoutNode::OneUp3D;
    case 6: return vtkRPLayoutNode::OneUpAxial;
    case 7: return vtkRPLayoutNode::OneUpSagittal;
    case 8: return vtkRPLayoutNode::OneUpCoronal;
    default: return vtkRPLayoutNode::FourUp;
  }
}

int SlicerLayoutFromArrangement(int arrangement) {
  switch (arrangement) {
    case vtkRPLayoutNode::OneUp3D: return 4;
    case vtkRPLayoutNode::OneUpAxial: return 6;
    case vtkRPLayoutNode::OneUpSagittal: return 7;
    case vtkRPLayoutNode::OneUpCoronal: return 8;
    default: return 3;
  }
}

}  // namespace rp
