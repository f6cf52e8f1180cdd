#include "rpProtection.h"

#include "rpPropertyText.h"

namespace rp {

void WriteProtection(const StructureProtection& protection, std::map<std::string, std::string>& out,
                     const std::string& protectedKey, const std::string& marginKey) {
  if (!protection.Protected) return;
  out[protectedKey] = "true";
  out[marginKey] = FormatPropertyNumber(protection.SafetyMarginMm);
}

StructureProtection ReadProtection(const std::map<std::string, std::string>& in, const std::string& protectedKey,
                          const std::string& marginKey, std::string* warning) {
  StructureProtection protection;
  const auto flag = in.find(protectedKey);
  protection.Protected = flag != in.end() && (flag->second == "true" || flag->second == "1");
  const auto margin = in.find(marginKey);
  if (!protection.Protected || margin == in.end()) return protection;
  double value = 0;
  if (!ParsePropertyNumber(margin->second, value) || value < 0) {
    if (warning) *warning = "safety margin '" + margin->second + "' is not a number of mm >= 0: 0 used";
    return protection;
  }
  protection.SafetyMarginMm = value;
  return protection;
}

}  // namespace rp
