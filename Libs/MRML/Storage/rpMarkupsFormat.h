#pragma once
// Slicer's fiducial files as text, without VTK: .mrk.json (markups schema v1.0.3; control points
// in the file's coordinateSystem, LPS by default as Slicer writes them) and .fcsv (Slicer's
// "# Markups fiducial file version = 4.x" CSV with "# CoordinateSystem = LPS|RAS|0|1"). Points
// here are RAS. The parsers never throw: a malformed file is false and `error` names the file
// (`source`) and the line or point. rpMarkupsIO reads and writes nodes with these; the markups
// fuzzer feeds them arbitrary bytes.
#include <string>
#include <vector>

#include "rpControlPoint.h"

namespace rp {

bool ParseMarkupsJson(const std::string& text, const std::string& source, std::vector<ControlPoint>& points,
                      std::string& error);
bool ParseFcsv(const std::string& text, const std::string& source, std::vector<ControlPoint>& points,
               std::string& error);
/// Always LPS, as Slicer ≥ 4.11 writes; `color` is the list's display colour.
std::string FormatMarkupsJson(const std::vector<ControlPoint>& points, const double color[3]);
std::string FormatFcsv(const std::vector<ControlPoint>& points);

}  // namespace rp
