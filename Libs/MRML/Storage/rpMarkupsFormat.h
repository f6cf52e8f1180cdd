#pragma once
// Slicer's markups files as text, without VTK: .mrk.json (markups schema v1.0.3, one markup per
// file: a point list "Fiducial", a "Line" or a "Plane"; control points and plane axes in the
// file's coordinateSystem, LPS by default as Slicer writes them) and .fcsv (Slicer's
// "# Markups fiducial file version = 4.x" CSV with "# CoordinateSystem = LPS|RAS|0|1"). Points
// here are RAS. The parsers never throw: a malformed file is false and `error` names the file
// (`source`) and the key, line or point. rpMarkupsIO reads and writes nodes with these; the
// markups fuzzer feeds them arbitrary bytes.
//
// A .mrk.json is written key for key as Slicer 5's vtkMRMLMarkupsJsonStorageNode (and, for a
// plane, vtkMRMLMarkupsPlaneJsonStorageNode) writes it, display block included, plus two keys the
// schema leaves open (its markup objects allow additional properties; Slicer reads past them):
// "name" (a schema key Slicer 5.0 does not write) and "attributes": the node's attributes and our
// fields as "RoboPlan.<field>", the same strings our MRML writer puts in the node's `attributes`.
#include <map>
#include <string>
#include <vector>

#include "rpControlPoint.h"

namespace rp {

/// One markup of a .mrk.json (RAS, mm).
struct MarkupsDocument {
  std::string Type = "Fiducial";  // "Fiducial", "Line", "Plane"
  std::string Name;               // "name" ("" when absent)
  std::vector<ControlPoint> Points;
  double Color[3] = {1.0, 0.5, 0.5};  // display selectedColor (read: else color)
  bool HasColor = false;              // read: the file had one
  bool Locked = false;
  /// "Plane": origin (control point 0 of a point-normal plane, the first of a 3-point one),
  /// unit normal and in-plane x axis, size (mm along x and y; 0 when the file gives none).
  double Origin[3] = {0, 0, 0};
  double Normal[3] = {0, 0, 1};
  double XAxis[3] = {1, 0, 0};
  double Size[2] = {0, 0};
  /// "attributes": node attributes and RoboPlan.<field> values.
  std::map<std::string, std::string> Attributes;
};

/// Reads markups[0]. `types` lists the types the caller accepts (empty: any of the three).
bool ParseMarkupsDocument(const std::string& text, const std::string& source, MarkupsDocument& document,
                          std::string& error, const std::vector<std::string>& types = {});
/// The type of markups[0], "" (with `error`) when the text is no markups file.
std::string PeekMarkupsType(const std::string& text, const std::string& source, std::string& error);
/// Always LPS, as Slicer >= 4.11 writes.
std::string FormatMarkupsDocument(const MarkupsDocument& document);

/// Point lists only (the "Fiducial" type), for callers that hold bare points.
bool ParseMarkupsJson(const std::string& text, const std::string& source, std::vector<ControlPoint>& points,
                      std::string& error);
std::string FormatMarkupsJson(const std::vector<ControlPoint>& points, const double color[3]);
bool ParseFcsv(const std::string& text, const std::string& source, std::vector<ControlPoint>& points,
               std::string& error);
std::string FormatFcsv(const std::vector<ControlPoint>& points);

}  // namespace rp
