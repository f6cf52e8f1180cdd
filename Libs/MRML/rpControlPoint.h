#pragma once
// One control point of a fiducial list (Slicer's markups control point), as plain data: what
// vtkRPFiducialListNode holds and what the .mrk.json/.fcsv parsers produce.
#include <string>

namespace rp {

struct ControlPoint {
  std::string ID;  // unique within the list (Slicer's control point "id")
  std::string Label;
  std::string Description;
  double Position[3] = {0, 0, 0};  // RAS, in the list's own coordinates (before its transform)
  bool Selected = true;
  bool Locked = false;
  bool Visible = true;
};

}  // namespace rp
