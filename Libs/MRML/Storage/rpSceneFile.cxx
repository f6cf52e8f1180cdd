#include "rpSceneFile.h"

#include <nlohmann/json.hpp>

namespace rp {

using nlohmann::json;

namespace {

// A JSON object whose values are all strings, into `out`; false when it is not one.
bool StringMap(const json& value, std::map<std::string, std::string>& out) {
  if (!value.is_object()) return false;
  for (const auto& [key, item] : value.items()) {
    if (!item.is_string()) return false;
    out[key] = item.get<std::string>();
  }
  return true;
}

std::string Text(const json& entry, const char* key) {
  const auto it = entry.find(key);
  return it != entry.end() && it->is_string() ? it->get<std::string>() : std::string();
}

SceneFileNode ParseNode(const json& entry) {
  SceneFileNode node;
  if (!entry.is_object()) {
    node.Problem = "a node entry is not a JSON object";
    return node;
  }
  node.Class = Text(entry, "class");
  node.ID = Text(entry, "id");
  node.Name = Text(entry, "name");
  node.DataFile = Text(entry, "dataFile");  // first: a saver must not overwrite it even if the rest is bad
  auto malformed = [&](const std::string& why) {
    node.Problem = "malformed entry (" + why + ")";
    return node;
  };
  for (const char* key : {"class", "id", "name"}) {
    if (entry.contains(key) && !entry[key].is_string()) return malformed(std::string("\"") + key + "\" is not text");
  }
  if (entry.contains("properties") && !StringMap(entry["properties"], node.Properties))
    return malformed("\"properties\" is not an object of texts");
  if (entry.contains("attributes") && !StringMap(entry["attributes"], node.Attributes))
    return malformed("\"attributes\" is not an object of texts");
  if (entry.contains("references")) {
    const json& references = entry["references"];
    if (!references.is_object()) return malformed("\"references\" is not an object");
    for (const auto& [role, ids] : references.items()) {
      if (!ids.is_array()) return malformed("references '" + role + "' is not a list");
      std::vector<std::string> list;
      for (const json& id : ids) {
        if (!id.is_string()) return malformed("a reference of '" + role + "' is not a node ID");
        list.push_back(id.get<std::string>());
      }
      node.References.emplace_back(role, std::move(list));
    }
  }
  if (entry.contains("dataFile") && node.DataFile.empty()) return malformed("\"dataFile\" is not a file name");
  return node;
}

}  // namespace

bool ParseSceneFile(const std::string& text, const std::string& source, SceneFileDocument& document,
                    std::string& error) {
  const json doc = json::parse(text, nullptr, false);
  if (doc.is_discarded() || !doc.is_object()) {
    error = "'" + source + "' is not a valid JSON scene file";
    return false;
  }
  const auto format = doc.find("format");
  if (format == doc.end() || !format->is_string() || format->get<std::string>() != "RoboPlan scene") {
    error = "'" + source + "' is not a RoboPlan scene (missing \"format\": \"RoboPlan scene\")";
    return false;
  }
  const auto version = doc.find("version");
  const int v = version != doc.end() && version->is_number_integer() && version->get<int64_t>() > 0 &&
                        version->get<int64_t>() <= 1000000
                    ? static_cast<int>(version->get<int64_t>())
                    : 0;
  if (v < 1 || v > SceneFileFormatVersion) {
    const std::string found = version == doc.end() ? std::string("(none)")
                              : version->is_number() ? version->dump()
                                                     : std::string("(not a number)");
    error = "'" + source + "' has scene format version " + found + "; this program reads versions 1 to " +
            std::to_string(SceneFileFormatVersion);
    return false;
  }
  SceneFileDocument parsed;
  parsed.Version = v;
  if (doc.contains("nodes")) {
    if (!doc["nodes"].is_array()) {
      error = "'" + source + "': \"nodes\" is not a list";
      return false;
    }
    for (const json& entry : doc["nodes"]) parsed.Nodes.push_back(ParseNode(entry));
  }
  // Only tells a save what it may replace: what is not a list of names is ignored, not an error.
  if (const auto owned = doc.find("ownedFiles"); owned != doc.end() && owned->is_array()) {
    for (const json& name : *owned)
      if (name.is_string()) parsed.OwnedFiles.push_back(name.get<std::string>());
  }
  document = std::move(parsed);
  return true;
}

std::string FormatSceneFile(const SceneFileDocument& document) {
  json doc;
  doc["format"] = "RoboPlan scene";
  doc["version"] = document.Version;
  doc["coordinateSystem"] = "RAS";
  doc["units"] = "mm";
  json nodes = json::array();
  for (const SceneFileNode& node : document.Nodes) {
    json entry;
    entry["class"] = node.Class;
    entry["id"] = node.ID;
    entry["name"] = node.Name;
    entry["properties"] = node.Properties;
    entry["attributes"] = node.Attributes;
    json references = json::object();
    for (const auto& [role, ids] : node.References) references[role] = ids;
    entry["references"] = references;
    if (!node.DataFile.empty()) entry["dataFile"] = node.DataFile;
    nodes.push_back(entry);
  }
  doc["nodes"] = nodes;
  if (!document.OwnedFiles.empty()) doc["ownedFiles"] = document.OwnedFiles;
  // Invalid UTF-8 in a name is replaced rather than thrown (dump's strict mode would throw).
  return doc.dump(2, ' ', false, json::error_handler_t::replace) + "\n";
}

}  // namespace rp
