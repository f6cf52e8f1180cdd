#pragma once
// Markups files of scene nodes in 3D Slicer's layouts (rpMarkupsFormat.h): .mrk.json for every
// vtkRPMarkupsNode (a fiducial list as "Fiducial", a trajectory or screw as "Line", a cut plane as
// "Plane"; our fields and the node's attributes in "attributes"), and .fcsv for fiducial lists.
#include <string>

class vtkRPFiducialListNode;
class vtkRPMarkupsNode;

namespace rp {

bool WriteMarkupsJson(const std::string& path, vtkRPMarkupsNode* node, std::string& error);
/// Reads a file of the node's markups type (a line into a trajectory...); the node is untouched
/// on failure.
bool ReadMarkupsJson(const std::string& path, vtkRPMarkupsNode* node, std::string& error);
bool WriteFcsv(const std::string& path, vtkRPFiducialListNode* node, std::string& error);
bool ReadFcsv(const std::string& path, vtkRPFiducialListNode* node, std::string& error);

/// The node class a .mrk.json loads into: vtkRPFiducialListNode, vtkRPTrajectoryNode (or the
/// subclass its "RoboPlan.Class" attribute names, e.g. vtkRPScrewNode) or vtkRPCutPlaneNode.
std::string MarkupsNodeClassForFile(const std::string& path, std::string& error);

/// Our node properties that a .mrk.json holds in Slicer's own keys (colour, plane axes and size),
/// so they are not repeated as RoboPlan.<field> attributes (there or in a .mrml).
bool IsMarkupsFileField(const std::string& key);

}  // namespace rp
