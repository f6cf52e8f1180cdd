#include "rpMarkupsFormat.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <sstream>

#include <nlohmann/json.hpp>

#include "rpLPSRAS.h"

// Both formats store positions in the file's coordinate system; points here are RAS. LPS ↔ RAS
// negates x and y. We always write LPS (what Slicer ≥ 4.11 writes) and read LPS and RAS.
namespace rp {
namespace {

const char* const MarkupsSchema =
    "https://raw.githubusercontent.com/slicer/slicer/master/Modules/Loadable/Markups/Resources/Schema/"
    "markups-schema-v1.0.3.json#";

std::string Lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

std::string Trim(const std::string& s) {
  const auto first = s.find_first_not_of(" \t\r\n");
  if (first == std::string::npos) return {};
  const auto last = s.find_last_not_of(" \t\r\n");
  return s.substr(first, last - first + 1);
}

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

bool ParseMarkupsJson(const std::string& text, const std::string& path, std::vector<ControlPoint>& points,
                      std::string& error) {
  nlohmann::json doc;
  try {
    doc = nlohmann::json::parse(text);
  } catch (const std::exception& e) {
    error = "'" + path + "' is not valid JSON (" + e.what() + ")";
    return false;
  }
  if (!doc.is_object() || !doc.contains("@schema") || !doc["@schema"].is_string() ||
      Lower(doc["@schema"].get<std::string>()).find("markups-schema-v1.") == std::string::npos) {
    error = "'" + path + "' is not a Slicer markups file (no \"@schema\" naming markups-schema-v1.x)";
    return false;
  }
  if (!doc.contains("markups") || !doc["markups"].is_array() || doc["markups"].empty()) {
    error = "'" + path + "' has no \"markups\" array";
    return false;
  }
  const nlohmann::json& markup = doc["markups"][0];
  if (!markup.is_object()) {
    error = "'" + path + "': markups[0] is not an object";
    return false;
  }
  // (value() throws when the key holds another type: read only strings.)
  const std::string type = markup.contains("type") && markup["type"].is_string() ? markup["type"].get<std::string>() : "";
  if (type != "Fiducial") {
    error = "'" + path + "': markups[0] is of type '" + type + "', expected a 'Fiducial' point list";
    return false;
  }
  int sign = -1;  // Slicer reads files without "coordinateSystem" as LPS
  if (markup.contains("coordinateSystem")) {
    const auto& cs = markup["coordinateSystem"];
    sign = cs.is_string() ? AxisSignFor(cs.get<std::string>()) : 0;
    if (sign == 0) {
      error = "'" + path + "': unsupported coordinateSystem " + cs.dump() + " (expected \"LPS\" or \"RAS\")";
      return false;
    }
  }
  if (markup.contains("coordinateUnits") && markup["coordinateUnits"].is_string() &&
      markup["coordinateUnits"].get<std::string>() != "mm") {
    error = "'" + path + "': coordinateUnits '" + markup["coordinateUnits"].get<std::string>() +
            "' is not supported (RoboPlan works in mm)";
    return false;
  }
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
    // those have no position to register with, so they are skipped.
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
    auto text = [&item](const char* key) {
      return item.contains(key) && item[key].is_string() ? item[key].get<std::string>() : std::string();
    };
    auto flag = [&item](const char* key, bool fallback) {
      return item.contains(key) && item[key].is_boolean() ? item[key].get<bool>() : fallback;
    };
    p.ID = text("id");
    p.Label = text("label");
    p.Description = text("description");
    p.Selected = flag("selected", true);
    p.Locked = flag("locked", false);
    p.Visible = flag("visibility", true);
    points.push_back(p);
  }
  return true;
}

std::string FormatMarkupsJson(const std::vector<ControlPoint>& controlPoints, const double color[3]) {
  nlohmann::ordered_json points = nlohmann::ordered_json::array();
  for (const auto& p : controlPoints) {
    nlohmann::ordered_json cp;
    cp["id"] = p.ID;
    cp["label"] = p.Label;
    cp["description"] = p.Description;
    cp["associatedNodeID"] = "";
    double lps[3] = {p.Position[0], p.Position[1], p.Position[2]};
    FlipLPSRASPoint(lps);
    cp["position"] = {lps[0], lps[1], lps[2]};
    // Identity orientation in RAS, written in LPS the way Slicer does (first two rows negated).
    cp["orientation"] = {-1.0, -0.0, -0.0, -0.0, -1.0, -0.0, 0.0, 0.0, 1.0};
    cp["selected"] = p.Selected;
    cp["locked"] = p.Locked;
    cp["visibility"] = p.Visible;
    cp["positionStatus"] = "defined";
    points.push_back(cp);
  }
  nlohmann::ordered_json markup;
  markup["type"] = "Fiducial";
  markup["coordinateSystem"] = "LPS";
  markup["coordinateUnits"] = "mm";
  markup["locked"] = false;
  markup["fixedNumberOfControlPoints"] = false;
  markup["labelFormat"] = "%N-%d";
  markup["lastUsedControlPointNumber"] = controlPoints.size();
  markup["controlPoints"] = points;
  markup["measurements"] = nlohmann::ordered_json::array();
  const double* c = color;
  markup["display"] = {{"visibility", true}, {"opacity", 1.0}, {"color", {c[0], c[1], c[2]}},
                       {"selectedColor", {c[0], c[1], c[2]}}};
  nlohmann::ordered_json doc;
  doc["@schema"] = MarkupsSchema;
  doc["markups"] = nlohmann::ordered_json::array({markup});
  return doc.dump(4, ' ', false, nlohmann::ordered_json::error_handler_t::replace) + "\n";  // never throws on bad UTF-8
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
