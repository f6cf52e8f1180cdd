#include "rpMaterial.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>

#include <nlohmann/json.hpp>

namespace rp {

namespace {
std::string Lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}
}  // namespace

int MaterialTable::Find(const std::string& tissue) const {
  const std::string key = Lower(tissue);
  for (size_t i = 0; i < this->Entries.size(); ++i)
    if (Lower(this->Entries[i].Tissue) == key) return static_cast<int>(i);
  return -1;
}

MaterialTable MaterialTable::Defaults() {
  MaterialTable t;
  t.Entries = {{"bone", 2.00, 0.0010, 0.40, 0.30, 1.0, 600},
               {"trabecular bone", 1.50, 0.0010, 0.35, 0.25, 0.25, 100},
               {"cartilage", 1.20, 0.0008, 0.03, 0.02},
               {"tendon", 0.90, 0.0008, 0.15, 0.10},
               {"ligament", 0.80, 0.0008, 0.15, 0.10},
               {"skin", 0.35, 0.0005, 0.50, 0.40},
               {"muscle", 0.25, 0.0006, 0.20, 0.15},
               {"fat", 0.08, 0.0004, 0.10, 0.08}};
  t.Default = t.Find("muscle");
  return t;
}

bool MaterialTable::Load(const std::string& path, std::string& error) {
  std::ifstream in(path);
  if (!in) {
    error = "materials: cannot open '" + path + "'";
    return false;
  }
  nlohmann::json doc;
  try {
    in >> doc;
  } catch (const std::exception& e) {
    error = "materials: '" + path + "' is not valid JSON (" + e.what() + ")";
    return false;
  }
  if (!doc.is_object() || !doc.contains("materials") || !doc["materials"].is_array()) {
    error = "materials: '" + path + "' has no \"materials\" array";
    return false;
  }
  std::vector<Material> entries;
  for (size_t i = 0; i < doc["materials"].size(); ++i) {
    const auto& e = doc["materials"][i];
    const std::string where = "materials: '" + path + "' entry " + std::to_string(i);
    if (!e.is_object() || !e.contains("tissue") || !e["tissue"].is_string()) {
      error = where + " has no \"tissue\" name";
      return false;
    }
    Material m;
    m.Tissue = e["tissue"].get<std::string>();
    auto number = [&](const char* key, double& out, bool required) {
      if (!e.contains(key)) {
        if (required) error = where + " (" + m.Tissue + ") lacks \"" + key + "\"";
        return !required;
      }
      if (!e[key].is_number() || !std::isfinite(e[key].get<double>()) || e[key].get<double>() < 0) {
        error = where + " (" + m.Tissue + "): \"" + key + "\" must be a non-negative number";
        return false;
      }
      out = e[key].get<double>();
      return true;
    };
    if (!number("stiffness", m.Stiffness, true) || !number("damping", m.Damping, true) ||
        !number("staticFriction", m.StaticFriction, false) || !number("dynamicFriction", m.DynamicFriction, false) ||
        !number("hardness", m.Hardness, false))
      return false;
    if (e.contains("ctMinHU")) {  // may be negative (HU)
      if (!e["ctMinHU"].is_number() || !std::isfinite(e["ctMinHU"].get<double>())) {
        error = where + " (" + m.Tissue + "): \"ctMinHU\" must be a number (HU)";
        return false;
      }
      if (m.Hardness <= 0) {
        error = where + " (" + m.Tissue + "): \"ctMinHU\" needs a \"hardness\" (only drillable tissues are classified by CT)";
        return false;
      }
      m.CTMinHU = e["ctMinHU"].get<double>();
    }
    if (m.DynamicFriction > m.StaticFriction) {
      error = where + " (" + m.Tissue + "): dynamicFriction exceeds staticFriction";
      return false;
    }
    entries.push_back(m);
  }
  if (entries.empty()) {
    error = "materials: '" + path + "' lists no materials";
    return false;
  }
  MaterialTable table;
  table.Entries = std::move(entries);
  table.Default = 0;
  if (doc.contains("default") && doc["default"].is_string()) {
    const int d = table.Find(doc["default"].get<std::string>());
    if (d < 0) {
      error = "materials: '" + path + "' default '" + doc["default"].get<std::string>() + "' is not listed";
      return false;
    }
    table.Default = d;
  }
  *this = std::move(table);
  return true;
}

}  // namespace rp
