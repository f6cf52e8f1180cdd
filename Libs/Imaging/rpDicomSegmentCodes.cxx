#include "rpDicomSegmentCodes.h"

#include <algorithm>
#include <cctype>
#include <iterator>

#include "rpDicomSegmentation.h"
#include "rpStrings.h"

namespace rp {

namespace {

const DicomSegmentCode SegmentCodes[] = {
    {"femur", "123037004", "Anatomical Structure", "71341001", "Femur", "bone"},
    {"tibia", "123037004", "Anatomical Structure", "12611008", "Tibia", "bone"},
    {"fibula", "123037004", "Anatomical Structure", "87342007", "Fibula", "bone"},
    {"patella", "123037004", "Anatomical Structure", "64234005", "Patella", "bone"},
    {"bone", "85756007", "Tissue", "272673000", "Bone", "bone"},
    {"", "85756007", "Tissue", "85756007", "Tissue", ""},
};

// Whether `key` is a whole word of `text` ("tibia" in "Left Tibia" and "tibia_2", not in
// "tibial cartilage" or "patellar tendon").
bool HasWord(const std::string& text, const std::string& key) {
  for (size_t at = text.find(key); at != std::string::npos; at = text.find(key, at + 1)) {
    const bool before = at == 0 || !std::isalpha(static_cast<unsigned char>(text[at - 1]));
    const size_t end = at + key.size();
    const bool after = end == text.size() || !std::isalpha(static_cast<unsigned char>(text[end]));
    if (before && after) return true;
  }
  return false;
}

}  // namespace

const DicomSegmentCode& DicomSegmentCodeFor(const std::string& id, const std::string& name,
                                            const std::string& tissueClass) {
  const std::string lowerId = Lower(id), lowerName = Lower(name);
  for (const DicomSegmentCode& code : SegmentCodes) {
    const std::string key = code.Key;
    if (key.empty()) return code;
    if (HasWord(lowerId, key) || HasWord(lowerName, key)) return code;
    if (key == "bone" && tissueClass == "bone") return code;
  }
  return SegmentCodes[std::size(SegmentCodes) - 1];
}

std::string DicomTissueClassOfType(const std::string& typeValue) {
  for (const DicomSegmentCode& code : SegmentCodes)
    if (typeValue == code.TypeValue) return code.TissueClass;
  return "";
}

std::string KnownTissueClass(const std::string& segmentName) { return DicomSegmentCodeFor("", segmentName, "").TissueClass; }

}  // namespace rp
