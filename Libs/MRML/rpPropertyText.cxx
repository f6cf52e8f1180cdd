#include "rpPropertyText.h"

#include <charconv>
#include <cmath>

namespace rp {

std::string FormatPropertyNumber(double value) {
  char text[32];
  const auto result = std::to_chars(text, text + sizeof(text), value);
  return std::string(text, result.ptr);
}

std::string FormatPropertyNumbers(const double* values, int count) {
  std::string text;
  for (int n = 0; n < count; ++n) text += (n ? " " : "") + FormatPropertyNumber(values[n]);
  return text;
}

bool ParsePropertyNumbers(const std::string& text, std::vector<double>& values, size_t count) {
  values.clear();
  const char* at = text.data();
  const char* end = text.data() + text.size();
  while (true) {
    while (at < end && (*at == ' ' || *at == '\t')) ++at;
    if (at == end) break;
    double value = 0;
    const auto result = std::from_chars(at, end, value);
    if (result.ec != std::errc() || !std::isfinite(value)) return false;
    if (result.ptr < end && *result.ptr != ' ' && *result.ptr != '\t') return false;
    values.push_back(value);
    at = result.ptr;
  }
  return count == 0 ? !values.empty() : values.size() == count;
}

bool ParsePropertyNumber(const std::string& text, double& value) {
  std::vector<double> values;
  if (!ParsePropertyNumbers(text, values, 1)) return false;
  value = values[0];
  return true;
}

}  // namespace rp
