#include "rpMaterial.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "rpResources.h"
#include "rpStrings.h"

namespace rp {

// Generated at configure time from Resources/Materials/materials.json (rpMaterialsBuiltIn.cxx).
const char* BuiltInMaterialsJson();

namespace {
constexpr const char* BuiltInSource = "built-in copy of Resources/Materials/materials.json";
}  // namespace

int MaterialTable::Find(const std::string& tissue) const {
  const std::string key = Lower(tissue);
  for (size_t i = 0; i < this->Entries.size(); ++i)
    if (Lower(this->Entries[i].Tissue) == key) return static_cast<int>(i);
  return -1;
}

std::vector<std::string> MaterialTable::TissueNames() const {
  std::vector<std::string> names;
  for (const Material& m : this->Entries) names.push_back(m.Tissue);
  return names;
}

MaterialTable MaterialTable::Defaults() {
  MaterialTable t;
  std::string error;
  // The build compiles the repository's file in; a broken file fails rpHapticsCoreTest.
  if (!t.Parse(BuiltInMaterialsJson(), BuiltInSource, error)) t = MaterialTable{};
  return t;
}

bool MaterialTable::Load(const std::string& path, std::string& error) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    error = "materials: cannot open '" + path + "'";
    return false;
  }
  std::ostringstream text;
  text << in.rdbuf();
  return this->Parse(text.str(), "'" + path + "'", error);
}

bool MaterialTable::Parse(const std::string& text, const std::string& source, std::string& error) {
  const nlohmann::json doc = nlohmann::json::parse(text, nullptr, false);
  if (doc.is_discarded()) {
    error = "materials: " + source + " is not valid JSON";
    return false;
  }
  if (!doc.is_object() || !doc.contains("materials") || !doc["materials"].is_array()) {
    error = "materials: " + source + " has no \"materials\" array";
    return false;
  }
  std::vector<Material> entries;
  for (size_t i = 0; i < doc["materials"].size(); ++i) {
    const auto& e = doc["materials"][i];
    const std::string where = "materials: " + source + " entry " + std::to_string(i);
    if (!e.is_object() || !e.contains("tissue") || !e["tissue"].is_string() || e["tissue"].get<std::string>().empty()) {
      error = where + " has no \"tissue\" name";
      return false;
    }
    Material m;
    m.Tissue = e["tissue"].get<std::string>();
    for (const Material& seen : entries) {
      if (Lower(seen.Tissue) == Lower(m.Tissue)) {
        error = where + ": tissue '" + m.Tissue + "' is listed twice";
        return false;
      }
    }
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
    error = "materials: " + source + " lists no materials";
    return false;
  }
  MaterialTable table;
  table.Entries = std::move(entries);
  table.Default = 0;
  table.Origin = source;
  if (doc.contains("default")) {
    if (!doc["default"].is_string()) {
      error = "materials: " + source + " \"default\" must be a tissue name";
      return false;
    }
    const int d = table.Find(doc["default"].get<std::string>());
    if (d < 0) {
      error = "materials: " + source + " default '" + doc["default"].get<std::string>() + "' is not listed";
      return false;
    }
    table.Default = d;
  }
  *this = std::move(table);
  return true;
}

bool LoadMaterialTable(MaterialTable& table, std::string& error, const std::string& path) {
  if (!path.empty()) return table.Load(path, error);
  const std::string resources = ResourcePath("Materials/materials.json");
  std::error_code ec;
  if (std::filesystem::exists(resources, ec)) return table.Load(resources, error);
  MaterialTable builtIn;
  if (!builtIn.Parse(BuiltInMaterialsJson(), BuiltInSource, error)) return false;
  table = std::move(builtIn);
  return true;
}

}  // namespace rp
