#include "rpLabelTable.h"

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <set>
#include <sstream>

#include <vtkNew.h>

#include "rpNodeStorage.h"
#include "rpSegmentationIO.h"
#include "vtkRPSegmentationNode.h"

namespace rp {

const LabelEntry* LabelTable::Find(long value) const {
  for (const auto& e : this->Entries)
    if (e.Value == value) return &e;
  return nullptr;
}

namespace {

bool ToLong(const std::string& text, long& value) {
  char* end = nullptr;
  value = std::strtol(text.c_str(), &end, 10);
  return !text.empty() && end && *end == '\0';
}

bool ToDouble(const std::string& text, double& value) {
  char* end = nullptr;
  value = std::strtod(text.c_str(), &end);
  return !text.empty() && end && *end == '\0' && std::isfinite(value);
}

// One entry from a line of either format; false with `why` on a malformed line.
bool ParseLine(const std::string& line, LabelEntry& entry, std::string& why) {
  const auto quote = line.find('"');
  std::istringstream in(line.substr(0, quote));
  std::vector<std::string> tokens;
  for (std::string t; in >> t;) tokens.push_back(t);
  if (tokens.empty() || !ToLong(tokens[0], entry.Value)) {
    why = "expected a label value first";
    return false;
  }
  double rgb[3];
  if (quote != std::string::npos) {
    // ITK-SNAP: IDX R G B A VIS MSH "LABEL"
    const auto close = line.find('"', quote + 1);
    if (close == std::string::npos) {
      why = "unterminated quoted label";
      return false;
    }
    entry.Name = line.substr(quote + 1, close - quote - 1);
    if (tokens.size() < 4) {
      why = "expected IDX R G B A VIS MSH \"LABEL\"";
      return false;
    }
    for (int c = 0; c < 3; ++c)
      if (!ToDouble(tokens[static_cast<size_t>(c + 1)], rgb[c])) {
        why = "colour component '" + tokens[static_cast<size_t>(c + 1)] + "' is not a number";
        return false;
      }
  } else {
    // Slicer: value name r g b [a]
    if (tokens.size() < 5) {
      why = "expected 'value name r g b a'";
      return false;
    }
    entry.Name = tokens[1];
    for (int c = 0; c < 3; ++c)
      if (!ToDouble(tokens[static_cast<size_t>(c + 2)], rgb[c])) {
        why = "colour component '" + tokens[static_cast<size_t>(c + 2)] + "' is not a number";
        return false;
      }
  }
  for (int c = 0; c < 3; ++c) {
    if (rgb[c] < 0 || rgb[c] > 255) {
      why = "colour components must be in 0..255";
      return false;
    }
    entry.Color[static_cast<size_t>(c)] = rgb[c] / 255.0;
  }
  return true;
}

// A .seg.nrrd's segments as a table.
bool ReadSegmentationTable(const std::string& path, LabelTable& table, std::string& error) {
  vtkNew<vtkRPSegmentationNode> segmentation;
  if (!ReadSegmentationFile(path, segmentation, error)) {
    error = "label table '" + path + "': " + error;
    return false;
  }
  LabelTable result;
  for (const auto& segment : segmentation->GetSegments()) {
    LabelEntry entry;
    entry.Value = segment.LabelValue;
    entry.Name = segment.Name.empty() ? segment.ID : segment.Name;
    for (size_t c = 0; c < 3; ++c) entry.Color[c] = segment.Color[c];
    entry.TissueClass = segment.TissueClass;
    result.Entries.push_back(entry);
  }
  if (result.Entries.empty()) {
    error = "label table '" + path + "': the segmentation has no segments";
    return false;
  }
  table = std::move(result);
  return true;
}

}  // namespace

bool ReadLabelTable(const std::string& path, LabelTable& table, std::string& error) {
  if (HasExtension(path, ".seg.nrrd")) return ReadSegmentationTable(path, table, error);
  std::ifstream in(path);
  if (!in) {
    error = "cannot open label table '" + path + "'";
    return false;
  }
  LabelTable result;
  std::set<long> values;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    const auto first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    LabelEntry entry;
    std::string why;
    if (!ParseLine(line.substr(first), entry, why)) {
      error = "label table '" + path + "' line " + std::to_string(number) + ": " + why;
      return false;
    }
    if (!values.insert(entry.Value).second) {
      error = "label table '" + path + "' line " + std::to_string(number) + ": value " + std::to_string(entry.Value) +
              " is listed twice";
      return false;
    }
    result.Entries.push_back(entry);
  }
  if (result.Entries.empty()) {
    error = "label table '" + path + "' has no entries (expected 'value name r g b a' or ITK-SNAP's format)";
    return false;
  }
  table = std::move(result);
  return true;
}

std::array<double, 3> DefaultLabelColor(long value) {
  // Hues a golden angle apart, two saturation levels alternating.
  const double hue = std::fmod(0.13 + 0.618033988749895 * static_cast<double>(value), 1.0) * 6.0;
  const double s = value % 2 ? 0.55 : 0.75, v = 0.9;
  const int sector = static_cast<int>(hue);
  const double f = hue - sector, p = v * (1 - s), q = v * (1 - s * f), t = v * (1 - s * (1 - f));
  switch (sector % 6) {
    case 0: return {v, t, p};
    case 1: return {q, v, p};
    case 2: return {p, v, t};
    case 3: return {p, q, v};
    case 4: return {t, p, v};
    default: return {v, p, q};
  }
}

}  // namespace rp
