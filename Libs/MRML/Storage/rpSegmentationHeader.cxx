#include "rpSegmentationHeader.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <set>
#include <sstream>

#include "rpStrings.h"

// Slicer's reader (vtkMRMLSegmentationStorageNode) keys segments by their index N in
// "Segment<N>_*"; files before Slicer 4.11 have no label value (segment N is label N+1).
namespace rp {
namespace {

bool ParseInt(const std::string& text, long& value) {
  const std::string t = Trim(text);
  if (t.empty()) return false;
  char* end = nullptr;
  value = std::strtol(t.c_str(), &end, 10);
  return end && *end == '\0';
}

bool ParseDoubles(const std::string& text, std::vector<double>& values) {
  std::istringstream in(text);
  values.clear();
  std::string token;
  while (in >> token) {
    char* end = nullptr;
    const double v = std::strtod(token.c_str(), &end);
    if (!end || *end != '\0' || !std::isfinite(v)) return false;
    values.push_back(v);
  }
  return true;
}

// "key1:value1|key2:value2|" (Slicer's tag list).
std::map<std::string, std::string> ParseTags(const std::string& text) {
  std::map<std::string, std::string> tags;
  std::istringstream in(text);
  std::string item;
  while (std::getline(in, item, '|')) {
    if (item.empty()) continue;
    const auto colon = item.find(':');
    if (colon == std::string::npos) {
      tags[item] = "";
    } else {
      tags[item.substr(0, colon)] = item.substr(colon + 1);
    }
  }
  return tags;
}

constexpr long MaxSegmentIndex = 1000000;

}  // namespace

bool ParseSegmentationHeader(const std::string& path, const std::map<std::string, std::string>& metadata,
                             std::vector<SegmentationHeaderSegment>& segments, std::string& error) {
  std::set<long> indices;
  for (const auto& [key, value] : metadata) {
    if (key.rfind("Segment", 0) != 0) continue;
    const auto underscore = key.find('_');
    if (underscore == std::string::npos || underscore == 7) continue;
    long index = 0;
    // Slicer numbers segments from 0; an index beyond any segmentation is not a segment key.
    if (!ParseInt(key.substr(7, underscore - 7), index) || index < 0 || index > MaxSegmentIndex) continue;
    indices.insert(index);
  }
  auto get = [&](long index, const std::string& field, std::string& value) {
    auto it = metadata.find("Segment" + std::to_string(index) + "_" + field);
    if (it == metadata.end()) return false;
    value = it->second;
    return true;
  };
  std::set<std::string> ids;
  for (long index : indices) {
    SegmentationHeaderSegment fs;
    auto& s = fs.Segment;
    const std::string prefix = "Segment" + std::to_string(index) + "_";
    if (!get(index, "ID", s.ID) || Trim(s.ID).empty()) {
      error = "'" + path + "': " + prefix + "ID is missing or empty";
      return false;
    }
    if (!ids.insert(s.ID).second) {
      error = "'" + path + "': segment ID '" + s.ID + "' appears twice";
      return false;
    }
    if (!get(index, "Name", s.Name)) s.Name = s.ID;
    std::string text;
    long value = 1;
    // Files written before Slicer 4.11 have no label value: segment N is label N+1.
    if (get(index, "LabelValue", text)) {
      if (!ParseInt(text, value) || value <= 0 || value > std::numeric_limits<int>::max()) {
        error = "'" + path + "': " + prefix + "LabelValue '" + text + "' is not a positive integer";
        return false;
      }
    } else {
      value = index + 1;
    }
    s.LabelValue = static_cast<int>(value);
    long layer = 0;
    if (get(index, "Layer", text) && (!ParseInt(text, layer) || layer < 0 || layer > std::numeric_limits<int>::max())) {
      error = "'" + path + "': " + prefix + "Layer '" + text + "' is not a non-negative integer";
      return false;
    }
    fs.Layer = static_cast<int>(layer);
    if (get(index, "Color", text)) {
      std::vector<double> rgb;
      if (!ParseDoubles(text, rgb) || rgb.size() != 3) {
        error = "'" + path + "': " + prefix + "Color '" + text + "' is not three numbers";
        return false;
      }
      for (int c = 0; c < 3; ++c) s.Color[c] = std::clamp(rgb[static_cast<size_t>(c)], 0.0, 1.0);
    }
    if (get(index, "Tags", text)) {
      const auto tags = ParseTags(text);
      auto it = tags.find(SegmentTissueTag);
      if (it != tags.end()) s.TissueClass = it->second;
      std::string warning;
      s.Protection = ReadProtection(tags, ProtectedSegmentTag, SafetyMarginSegmentTag, &warning);
      if (!warning.empty()) {
        error = "'" + path + "': " + prefix + "Tags: " + warning;
        return false;
      }
    }
    segments.push_back(fs);
  }
  return true;
}

}  // namespace rp
