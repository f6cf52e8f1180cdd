#include "rpStrings.h"

#include <algorithm>
#include <cctype>
#include <cstdio>

namespace rp {

std::string Trim(const std::string& text) {
  size_t begin = 0, end = text.size();
  while (begin < end && std::isspace(static_cast<unsigned char>(text[begin]))) ++begin;
  while (end > begin && std::isspace(static_cast<unsigned char>(text[end - 1]))) --end;
  return text.substr(begin, end - begin);
}

std::string Lower(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return text;
}

std::string Fixed(double value, int digits) {
  char text[384];  // DBL_MAX with 40 decimals fits
  std::snprintf(text, sizeof(text), "%.*f", digits, value);
  return text;
}

}  // namespace rp
