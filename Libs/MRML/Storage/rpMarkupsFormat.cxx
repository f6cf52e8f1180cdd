#include "rpMarkupsFormat.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <sstream>

#include <nlohmann/json.hpp>

#include "rpLPSRAS.h"
#include "rpStrings.h"

// Both formats store positions in the file's coordinate system; points here are RAS. LPS ↔ RAS
// negates x and y. We always write LPS (what Slicer ≥ 4.11 writes) and read LPS and RAS.
namespace rp {
namespace {

const char* const MarkupsSchema =
    "https://raw.githubusercontent.com/slicer/slicer/master/Modules/Loadable/Markups/Resources/Schema/"
    "markups-schema-v1.0.3.json#";

// Slicer's markups coordinate system names: "RAS"/"LPS" (json), also "0"/"1" (old .fcsv).
// Returns +1 for RAS, -1 for LPS, 0 when unknown (the sign applied to x and y).
int AxisSignFor(const std::string& value) {
  const std::string v = Lower(Trim(value));
  if (v == "ras" || v == "0") return 1;
  if (v == "lps" || v == "1") return -1;
  return 0;
}

// ---- .mrk.json

bool ReadJsonVector(const nlohmann::json& item, size_t size, double* out) {
  if (!item.is_array() || item.size() != size) return false;
  for (size_t i = 0; i < size; ++i) {
    if (!item[i].is_number()) return false;
    out[i] = item[i].get<double>();
  }
  return true;
}

// ---- .fcsv

// Splits one CSV line with Slicer's quoting: fields holding a comma or quote are wrapped in
// double quotes, and a quote inside is doubled.
std::vector<std::string> SplitCsv(const std::string& line) {
  std::vector<std::string> fields(1);
  bool quoted = false;
  for (size_t i = 0; i < line.size(); ++i) {
    const char ch = line[i];
    if (quoted) {
      if (ch == '"' && i + 1 < line.size() && line[i + 1] == '"') {
        fields.back() += '"';
        ++i;
      } else if (ch == '"') {
        quoted = false;
      } else {
        fields.back() += ch;
      }
    } else if (ch == '"') {
      quoted = true;
    } else if (ch == ',') {
      fields.emplace_back();
    } else if (ch != '\r') {
      fields.back() += ch;
    }
  }
  return fields;
}

std::string QuoteCsv(const std::string& field) {
  // Quoted too when it starts with '#' (a comment line otherwise) or holds a line break.
  if (field.find_first_of(",\"\n\r") == std::string::npos && (field.empty() || field[0] != '#')) return field;
  std::string quoted = "\"";
  for (char ch : field) {
    if (ch == '"') quoted += '"';
    quoted += (ch == '\n' || ch == '\r') ? ' ' : ch;
  }
  return quoted + "\"";
}

bool ParseDouble(const std::string& text, double& value) {
  const std::string t = Trim(text);
  if (t.empty()) return false;
  std::istringstream ss(t);
  ss.imbue(std::locale::classic());
  ss >> value;
  return !ss.fail() && ss.eof() && std::isfinite(value);
}

}  // namespace

namespace {

// The file's axis sign (LPS: -1, RAS: +1), with `error` set on an unknown system.
bool ReadCoordinateSign(const nlohmann::json& markup, const std::string& path, int& sign, std::string& error) {
  sign = -1;  // Slicer reads files without "coordinateSystem" as LPS
  if (!markup.contains("coordinateSystem")) return true;
  const auto& cs = markup["coordinateSystem"];
  sign = cs.is_string() ? AxisSignFor(cs.get<std::string>()) : 0;
  if (sign == 0) error = "'" + path + "': unsupported coordinateSystem " + cs.dump() + " (expected \"LPS\" or \"RAS\")";
  return sign != 0;
}

std::string TextOf(const nlohmann::json& item, const char* key) {
  return item.contains(key) && item[key].is_string() ? item[key].get<std::string>() : std::string();
}

bool FlagOf(const nlohmann::json& item, const char* key, bool fallback) {
  return item.contains(key) && item[key].is_boolean() ? item[key].get<bool>() : fallback;
}

bool ReadControlPoints(const nlohmann::json& markup, const std::string& path, int sign,
                       std::vector<ControlPoint>& points, std::string& error) {
  if (!markup.contains("controlPoints")) return true;  // an empty list is valid
  const auto& items = markup["controlPoints"];
  if (!items.is_array()) {
    error = "'" + path + "': controlPoints is not an array";
    return false;
  }
  for (size_t i = 0; i < items.size(); ++i) {
    const auto& item = items[i];
    const std::string where = "'" + path + "': control point " + std::to_string(i + 1);
    if (!item.is_object()) {
      error = where + " is not an object";
      return false;
    }
    // Slicer writes "position": "" for points not placed yet (positionStatus "undefined"/"preview");
    // those have no position to plan or register with, so they are skipped.
    const std::string status = !item.contains("positionStatus")       ? std::string("defined")
                               : item["positionStatus"].is_string() ? item["positionStatus"].get<std::string>()
                                                                    : std::string("(not text)");
    if (status != "defined" && status != "undefined" && status != "preview") {
      error = where + " has an invalid positionStatus '" + status + "'";
      return false;
    }
    if (status != "defined") continue;
    ControlPoint p;
    if (!item.contains("position") || !ReadJsonVector(item["position"], 3, p.Position)) {
      error = where + ": position must be an array of 3 numbers";
      return false;
    }
    if (!std::isfinite(p.Position[0]) || !std::isfinite(p.Position[1]) || !std::isfinite(p.Position[2])) {
      error = where + ": position is not finite";
      return false;
    }
    if (sign < 0) FlipLPSRASPoint(p.Position);
    p.ID = TextOf(item, "id");
    p.Label = TextOf(item, "label");
    p.Description = TextOf(item, "description");
    p.Selected = FlagOf(item, "selected", true);
    p.Locked = FlagOf(item, "locked", false);
    p.Visible = FlagOf(item, "visibility", true);
    points.push_back(p);
  }
  return true;
}

double Dot3(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

bool Unit(double v[3]) {
  const double n = std::sqrt(Dot3(v, v));
  if (!(n > 1e-12) || !std::isfinite(n)) return false;
  for (int i = 0; i < 3; ++i) v[i] /= n;
  return true;
}

void Cross3(const double a[3], const double b[3], double c[3]) {
  c[0] = a[1] * b[2] - a[2] * b[1], c[1] = a[2] * b[0] - a[0] * b[2], c[2] = a[0] * b[1] - a[1] * b[0];
}

// A 4x4 of the file (row-major, in its coordinate system) in RAS.
bool ReadMatrix(const nlohmann::json& markup, const char* key, int sign, double m[16]) {
  if (!markup.contains(key) || !ReadJsonVector(markup[key], 16, m)) return false;
  for (int i = 0; i < 16; ++i)
    if (!std::isfinite(m[i])) return false;
  if (sign < 0) FlipLPSRASIndexToSpace(m);  // S M: what Slicer writes (its first two rows negated)
  return true;
}

// Plane geometry as Slicer computes it: objectToNode = baseToNode * objectToBase (origin its
// translation, x and the normal its first and third columns); without the matrices, from the
// "center"/"normal" keys or the control points (3 points: Slicer's CalculateAxesFromPoints).
bool ReadPlane(const nlohmann::json& markup, const std::string& path, int sign, MarkupsDocument& doc,
               std::string& error) {
  double objectToBase[16], baseToNode[16];
  const auto& p = doc.Points;
  bool ok = false;
  if (ReadMatrix(markup, "objectToBase", sign, objectToBase) && ReadMatrix(markup, "baseToNode", sign, baseToNode)) {
    double m[16];
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) {
        m[4 * r + c] = 0;
        for (int k = 0; k < 4; ++k) m[4 * r + c] += baseToNode[4 * r + k] * objectToBase[4 * k + c];
      }
    for (int i = 0; i < 3; ++i) doc.Origin[i] = m[4 * i + 3], doc.XAxis[i] = m[4 * i], doc.Normal[i] = m[4 * i + 2];
    ok = Unit(doc.Normal) && Unit(doc.XAxis);
  } else if (p.size() >= 3 && TextOf(markup, "planeType") != "pointNormal") {
    double to2[3];
    for (int i = 0; i < 3; ++i)
      doc.Origin[i] = p[0].Position[i], doc.XAxis[i] = p[1].Position[i] - p[0].Position[i],
      to2[i] = p[2].Position[i] - p[0].Position[i];
    ok = Unit(doc.XAxis);
    Cross3(doc.XAxis, to2, doc.Normal);
    ok = ok && Unit(doc.Normal);
  } else if (!p.empty()) {
    for (int i = 0; i < 3; ++i) doc.Origin[i] = p[0].Position[i];
    ok = !markup.contains("normal") || (ReadJsonVector(markup["normal"], 3, doc.Normal) && Unit(doc.Normal));
    if (ok && markup.contains("normal") && sign < 0) FlipLPSRASPoint(doc.Normal);
    if (ok) {  // any in-plane x axis
      const double a[3] = {std::fabs(doc.Normal[0]) < 0.9 ? 1.0 : 0.0, std::fabs(doc.Normal[0]) < 0.9 ? 0.0 : 1.0, 0};
      double y[3];
      Cross3(doc.Normal, a, y);
      Cross3(y, doc.Normal, doc.XAxis);
      ok = Unit(doc.XAxis);
    }
  } else {
    error = "'" + path + "': the plane has no placed control point";
    return false;
  }
  if (!ok) {
    error = "'" + path + "': the plane's normal or axes are zero or not numbers";
    return false;
  }
  double bounds[4];
  if (markup.contains("planeBounds") && ReadJsonVector(markup["planeBounds"], 4, bounds))
    doc.Size[0] = bounds[1] - bounds[0], doc.Size[1] = bounds[3] - bounds[2];
  else if (markup.contains("size") && markup["size"].is_array() && markup["size"].size() >= 2)
    for (size_t i = 0; i < 2; ++i) doc.Size[i] = markup["size"][i].is_number() ? markup["size"][i].get<double>() : 0.0;
  for (double& v : doc.Size)
    if (!std::isfinite(v) || v < 0) v = 0;
  return true;
}

void ReadDisplayAndAttributes(const nlohmann::json& markup, MarkupsDocument& doc) {
  doc.Name = TextOf(markup, "name");
  doc.Locked = FlagOf(markup, "locked", false);
  if (markup.contains("display") && markup["display"].is_object()) {
    const auto& display = markup["display"];
    double color[3];
    if ((display.contains("selectedColor") && ReadJsonVector(display["selectedColor"], 3, color)) ||
        (display.contains("color") && ReadJsonVector(display["color"], 3, color))) {
      for (int i = 0; i < 3; ++i) doc.Color[i] = std::isfinite(color[i]) ? std::clamp(color[i], 0.0, 1.0) : 1.0;
      doc.HasColor = true;
    }
  }
  if (markup.contains("attributes") && markup["attributes"].is_object())
    for (const auto& [key, value] : markup["attributes"].items())
      if (value.is_string()) doc.Attributes[key] = value.get<std::string>();
}

// The document and its first markup, with the schema checked.
const nlohmann::json* FirstMarkup(const nlohmann::json& doc, const std::string& path, std::string& error) {
  if (!doc.is_object() || !doc.contains("@schema") || !doc["@schema"].is_string() ||
      Lower(doc["@schema"].get<std::string>()).find("markups-schema-v1.") == std::string::npos) {
    error = "'" + path + "' is not a Slicer markups file (no \"@schema\" naming markups-schema-v1.x)";
    return nullptr;
  }
  if (!doc.contains("markups") || !doc["markups"].is_array() || doc["markups"].empty()) {
    error = "'" + path + "' has no \"markups\" array";
    return nullptr;
  }
  if (!doc["markups"][0].is_object()) {
    error = "'" + path + "': markups[0] is not an object";
    return nullptr;
  }
  return &doc["markups"][0];
}

bool ParseJsonText(const std::string& text, const std::string& path, nlohmann::json& doc, std::string& error) {
  try {
    doc = nlohmann::json::parse(text);
  } catch (const std::exception& e) {
    error = "'" + path + "' is not valid JSON (" + e.what() + ")";
    return false;
  }
  return true;
}

}  // namespace

std::string PeekMarkupsType(const std::string& text, const std::string& path, std::string& error) {
  nlohmann::json doc;
  if (!ParseJsonText(text, path, doc, error)) return "";
  const nlohmann::json* markup = FirstMarkup(doc, path, error);
  return markup ? TextOf(*markup, "type") : std::string();
}

bool ParseMarkupsDocument(const std::string& text, const std::string& path, MarkupsDocument& document,
                          std::string& error, const std::vector<std::string>& types) {
  nlohmann::json doc;
  if (!ParseJsonText(text, path, doc, error)) return false;
  const nlohmann::json* found = FirstMarkup(doc, path, error);
  if (!found) return false;
  const nlohmann::json& markup = *found;
  MarkupsDocument out;
  out.Type = TextOf(markup, "type");
  const std::vector<std::string> known = {"Fiducial", "Line", "Plane"};
  const std::vector<std::string>& accepted = types.empty() ? known : types;
  if (std::find(accepted.begin(), accepted.end(), out.Type) == accepted.end()) {
    std::string list;
    for (const auto& t : accepted) list += (list.empty() ? "'" : ", '") + t + "'";
    error = "'" + path + "': markups[0] is of type '" + out.Type + "', expected " + list;
    return false;
  }
  int sign = -1;
  if (!ReadCoordinateSign(markup, path, sign, error)) return false;
  if (markup.contains("coordinateUnits") && markup["coordinateUnits"].is_string() &&
      markup["coordinateUnits"].get<std::string>() != "mm") {
    error = "'" + path + "': coordinateUnits '" + markup["coordinateUnits"].get<std::string>() +
            "' is not supported (RoboPlan works in mm)";
    return false;
  }
  if (!ReadControlPoints(markup, path, sign, out.Points, error)) return false;
  if (out.Type == "Line" && out.Points.size() > 2) {
    error = "'" + path + "': a line has " + std::to_string(out.Points.size()) + " control points (at most 2)";
    return false;
  }
  if (out.Type == "Plane" && !ReadPlane(markup, path, sign, out, error)) return false;
  ReadDisplayAndAttributes(markup, out);
  document = std::move(out);
  return true;
}

bool ParseMarkupsJson(const std::string& text, const std::string& path, std::vector<ControlPoint>& points,
                      std::string& error) {
  MarkupsDocument document;
  if (!ParseMarkupsDocument(text, path, document, error, {"Fiducial"})) return false;
  points.insert(points.end(), document.Points.begin(), document.Points.end());
  return true;
}

std::string FormatMarkupsJson(const std::vector<ControlPoint>& controlPoints, const double color[3]) {
  MarkupsDocument document;
  document.Points = controlPoints;
  for (int i = 0; i < 3; ++i) document.Color[i] = color[i];
  return FormatMarkupsDocument(document);
}

namespace {

using OrderedJson = nlohmann::ordered_json;

OrderedJson Vector(const double* v, int n) {
  OrderedJson a = OrderedJson::array();
  for (int i = 0; i < n; ++i) a.push_back(v[i]);
  return a;
}

OrderedJson ControlPointsJson(const std::vector<ControlPoint>& controlPoints) {
  OrderedJson points = OrderedJson::array();
  for (const auto& p : controlPoints) {
    OrderedJson cp;
    cp["id"] = p.ID;
    cp["label"] = p.Label;
    cp["description"] = p.Description;
    cp["associatedNodeID"] = "";
    double lps[3] = {p.Position[0], p.Position[1], p.Position[2]};
    FlipLPSRASPoint(lps);
    cp["position"] = Vector(lps, 3);
    // Identity orientation in RAS, written in LPS the way Slicer does (first two rows negated).
    cp["orientation"] = {-1.0, -0.0, -0.0, -0.0, -1.0, -0.0, 0.0, 0.0, 1.0};
    cp["selected"] = p.Selected;
    cp["locked"] = p.Locked;
    cp["visibility"] = p.Visible;
    cp["positionStatus"] = "defined";
    points.push_back(cp);
  }
  return points;
}

// The plane's keys as vtkMRMLMarkupsPlaneJsonStorageNode writes them for a point-normal plane of
// absolute size: objectToBase identity, baseToNode = [x y normal | origin], in LPS.
void AddPlaneKeys(const MarkupsDocument& d, OrderedJson& markup) {
  double y[3], baseToNode[16] = {0}, objectToBase[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1},
               orientation[9];
  Cross3(d.Normal, d.XAxis, y);
  for (int i = 0; i < 3; ++i) {
    baseToNode[4 * i] = d.XAxis[i], baseToNode[4 * i + 1] = y[i], baseToNode[4 * i + 2] = d.Normal[i];
    baseToNode[4 * i + 3] = d.Origin[i];
    orientation[3 * i] = d.XAxis[i], orientation[3 * i + 1] = y[i], orientation[3 * i + 2] = d.Normal[i];
  }
  baseToNode[15] = 1;
  FlipLPSRASIndexToSpace(baseToNode);
  FlipLPSRASIndexToSpace(objectToBase);
  for (int i = 0; i < 6; ++i) orientation[i] = -orientation[i];  // the 3x3 alike: S R
  double center[3] = {d.Origin[0], d.Origin[1], d.Origin[2]}, normal[3] = {d.Normal[0], d.Normal[1], d.Normal[2]};
  FlipLPSRASPoint(center);
  FlipLPSRASPoint(normal);
  const double size[3] = {d.Size[0], d.Size[1], 0.0};
  const double bounds[4] = {-d.Size[0] / 2, d.Size[0] / 2, -d.Size[1] / 2, d.Size[1] / 2};
  markup["planeType"] = "pointNormal";
  markup["sizeMode"] = "absolute";
  markup["autoScalingFactor"] = 1.0;
  markup["center"] = Vector(center, 3);
  markup["normal"] = Vector(normal, 3);
  markup["objectToBase"] = Vector(objectToBase, 16);
  markup["baseToNode"] = Vector(baseToNode, 16);
  markup["orientation"] = Vector(orientation, 9);
  markup["size"] = Vector(size, 3);
  markup["planeBounds"] = Vector(bounds, 4);
}

// What Slicer measures of each type (vtkMRMLMeasurementLength of a line, enabled; the plane's
// area, disabled); point lists measure nothing.
OrderedJson Measurements(const MarkupsDocument& d) {
  OrderedJson list = OrderedJson::array();
  if (d.Type == "Line" && d.Points.size() == 2) {
    double length2 = 0;
    for (int i = 0; i < 3; ++i) length2 += std::pow(d.Points[1].Position[i] - d.Points[0].Position[i], 2);
    list.push_back({{"name", "length"}, {"enabled", true}, {"value", std::sqrt(length2)}, {"units", "mm"},
                    {"printFormat", "%-#4.4g%s"}});
  } else if (d.Type == "Plane") {
    list.push_back({{"name", "area"}, {"enabled", false}, {"units", "cm2"}, {"printFormat", "%-#4.4g%s"}});
  }
  return list;
}

// vtkMRMLMarkupsDisplayNode's properties as its JSON writer lists them: our colour as colour and
// selected colour, Slicer's defaults for the rest.
OrderedJson Display(const double c[3]) {
  OrderedJson display;
  display["visibility"] = true;
  display["opacity"] = 1.0;
  display["color"] = Vector(c, 3);
  display["selectedColor"] = Vector(c, 3);
  display["activeColor"] = {0.4, 1.0, 0.0};
  display["propertiesLabelVisibility"] = true;
  display["pointLabelsVisibility"] = false;
  display["textScale"] = 3.0;
  display["glyphType"] = "Sphere3D";
  display["glyphScale"] = 3.0;
  display["glyphSize"] = 5.0;
  display["useGlyphScale"] = true;
  display["sliceProjection"] = false;
  display["sliceProjectionUseFiducialColor"] = true;
  display["sliceProjectionOutlinedBehindSlicePlane"] = false;
  display["sliceProjectionColor"] = {1.0, 1.0, 1.0};
  display["sliceProjectionOpacity"] = 0.6;
  display["lineThickness"] = 0.2;
  display["lineColorFadingStart"] = 1.0;
  display["lineColorFadingEnd"] = 10.0;
  display["lineColorFadingSaturation"] = 1.0;
  display["lineColorFadingHueOffset"] = 0.0;
  display["handlesInteractive"] = false;
  display["translationHandleVisibility"] = true;
  display["rotationHandleVisibility"] = true;
  display["scaleHandleVisibility"] = true;
  display["interactionHandleScale"] = 3.0;
  display["snapMode"] = "toVisibleSurface";
  return display;
}

}  // namespace

std::string FormatMarkupsDocument(const MarkupsDocument& d) {
  OrderedJson markup;
  markup["type"] = d.Type;
  markup["coordinateSystem"] = "LPS";
  markup["coordinateUnits"] = "mm";
  markup["locked"] = d.Locked;
  markup["fixedNumberOfControlPoints"] = false;
  markup["labelFormat"] = "%N-%d";
  markup["lastUsedControlPointNumber"] = d.Points.size();
  if (d.Type == "Plane") AddPlaneKeys(d, markup);
  markup["controlPoints"] = ControlPointsJson(d.Points);
  markup["measurements"] = Measurements(d);
  markup["display"] = Display(d.Color);
  if (!d.Name.empty()) markup["name"] = d.Name;
  if (!d.Attributes.empty()) markup["attributes"] = d.Attributes;
  OrderedJson doc;
  doc["@schema"] = MarkupsSchema;
  doc["markups"] = OrderedJson::array({markup});
  return doc.dump(4, ' ', false, OrderedJson::error_handler_t::replace) + "\n";  // never throws on bad UTF-8
}

bool ParseFcsv(const std::string& text, const std::string& path, std::vector<ControlPoint>& points, std::string& error) {
  std::istringstream in(text);
  std::string line;
  int sign = 1;  // files written before the CoordinateSystem line existed are RAS
  bool sawVersion = false;
  std::vector<std::string> columns = {"id", "x", "y", "z", "ow", "ox", "oy", "oz",
                                      "vis", "sel", "lock", "label", "desc", "associatedNodeID"};
  int lineNumber = 0;
  while (std::getline(in, line)) {
    ++lineNumber;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (Trim(line).empty()) continue;
    if (line[0] == '#') {
      const auto eq = line.find('=');
      if (eq == std::string::npos) continue;
      const std::string key = Lower(Trim(line.substr(1, eq - 1)));
      const std::string value = Trim(line.substr(eq + 1));
      if (key.rfind("markups fiducial file version", 0) == 0) {
        sawVersion = true;
      } else if (key == "coordinatesystem") {
        sign = AxisSignFor(value);
        if (sign == 0) {
          error = "'" + path + "': unsupported CoordinateSystem '" + value + "' (expected RAS, LPS, 0 or 1)";
          return false;
        }
      } else if (key == "columns") {
        columns = SplitCsv(value);
        for (auto& c : columns) c = Trim(c);
      }
      continue;
    }
    if (!sawVersion) {
      error = "'" + path + "' is not a Slicer fiducial file (no '# Markups fiducial file version' header)";
      return false;
    }
    const auto fields = SplitCsv(line);
    auto column = [&](const char* name) -> const std::string* {
      for (size_t i = 0; i < columns.size() && i < fields.size(); ++i) {
        if (columns[i] == name) return &fields[i];
      }
      return nullptr;
    };
    const std::string where = "'" + path + "' line " + std::to_string(lineNumber);
    ControlPoint p;
    const char* axes[3] = {"x", "y", "z"};
    for (int k = 0; k < 3; ++k) {
      const std::string* v = column(axes[k]);
      if (!v || !ParseDouble(*v, p.Position[k])) {
        error = where + ": missing or invalid " + axes[k] + " coordinate";
        return false;
      }
    }
    if (sign < 0) FlipLPSRASPoint(p.Position);
    auto flag = [&](const char* name, bool fallback) {
      const std::string* v = column(name);
      return v && !Trim(*v).empty() ? Trim(*v) != "0" : fallback;
    };
    if (const std::string* v = column("id")) p.ID = *v;
    if (const std::string* v = column("label")) p.Label = *v;
    if (const std::string* v = column("desc")) p.Description = *v;
    p.Visible = flag("vis", true);
    p.Selected = flag("sel", true);
    p.Locked = flag("lock", false);
    points.push_back(p);
  }
  if (!sawVersion) {
    error = "'" + path + "' is not a Slicer fiducial file (no '# Markups fiducial file version' header)";
    return false;
  }
  return true;
}

std::string FormatFcsv(const std::vector<ControlPoint>& controlPoints) {
  std::ostringstream out;
  out.imbue(std::locale::classic());
  out.precision(17);
  out << "# Markups fiducial file version = 4.11\n"
      << "# CoordinateSystem = LPS\n"
      << "# columns = id,x,y,z,ow,ox,oy,oz,vis,sel,lock,label,desc,associatedNodeID\n";
  for (const auto& p : controlPoints) {
    double lps[3] = {p.Position[0], p.Position[1], p.Position[2]};
    FlipLPSRASPoint(lps);
    out << QuoteCsv(p.ID) << "," << lps[0] << "," << lps[1] << "," << lps[2]
        << ",0,0,0,1," << (p.Visible ? 1 : 0) << "," << (p.Selected ? 1 : 0) << "," << (p.Locked ? 1 : 0) << ","
        << QuoteCsv(p.Label) << "," << QuoteCsv(p.Description) << ",\n";
  }
  return out.str();
}

}  // namespace rp
