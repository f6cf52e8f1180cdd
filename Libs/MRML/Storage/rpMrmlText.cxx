#include "rpMrmlText.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>

namespace rp {
namespace {

void ReplaceAll(std::string& text, const std::string& from, const std::string& to) {
  for (size_t at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size()))
    text.replace(at, from.size(), to);
}

// Slicer's URL encoding table, in its encoding order.
const std::pair<const char*, const char*> UrlCodes[] = {
    {"%", "%25"}, {" ", "%20"}, {"'", "%27"}, {">", "%3E"}, {"<", "%3C"}, {"\"", "%22"}};

}  // namespace

std::string MrmlUrlEncode(const std::string& text) {
  std::string out = text;
  for (const auto& [plain, code] : UrlCodes) ReplaceAll(out, plain, code);
  return out;
}

std::string MrmlUrlDecode(const std::string& text) {
  std::string out = text;
  for (int n = static_cast<int>(std::size(UrlCodes)) - 1; n >= 0; --n) ReplaceAll(out, UrlCodes[n].second, UrlCodes[n].first);
  return out;
}

std::string MrmlXmlEscape(const std::string& text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&apos;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '\n': out += "&#10;"; break;
      case '\r': out += "&#13;"; break;
      default: out += c;
    }
  }
  return out;
}

std::string FormatMrmlAttributes(const std::map<std::string, std::string>& attributes) {
  std::string out;
  for (const auto& [key, value] : attributes) {
    std::string encoded = value;
    ReplaceAll(encoded, "%", "%25");
    ReplaceAll(encoded, ";", "%3B");
    out += (out.empty() ? "" : ";") + key + ":" + encoded;
  }
  return out;
}

std::map<std::string, std::string> ParseMrmlAttributes(const std::string& text) {
  std::map<std::string, std::string> attributes;
  std::stringstream list(text);
  std::string item;
  while (std::getline(list, item, ';')) {
    const size_t colon = item.find(':');
    if (item.empty()) continue;
    std::string value = colon == std::string::npos ? std::string() : item.substr(colon + 1);
    ReplaceAll(value, "%3B", ";");
    ReplaceAll(value, "%25", "%");
    attributes[item.substr(0, colon)] = value;
  }
  return attributes;
}

std::string FormatMrmlReferences(const MrmlReferences& references) {
  std::string out;
  for (const auto& [role, ids] : references) {
    std::string list;
    for (const auto& id : ids)
      if (!id.empty()) list += (list.empty() ? "" : " ") + id;
    if (!list.empty()) out += role + ":" + list + ";";
  }
  return out;
}

MrmlReferences ParseMrmlReferences(const std::string& text) {
  MrmlReferences references;
  std::stringstream list(text);
  std::string item;
  while (std::getline(list, item, ';')) {
    const size_t colon = item.find(':');
    if (colon == std::string::npos || colon == 0) continue;
    const std::string role = item.substr(0, colon);
    bool seen = false;
    for (const auto& entry : references) seen = seen || entry.first == role;
    if (seen) continue;
    std::stringstream ids(item.substr(colon + 1));
    std::vector<std::string> values;
    for (std::string id; ids >> id;) values.push_back(id);
    if (!values.empty()) references.emplace_back(role, std::move(values));
  }
  return references;
}

std::string FormatNumbers(const double* values, int count) {
  std::string out;
  char buffer[40];
  for (int n = 0; n < count; ++n) {
    std::snprintf(buffer, sizeof(buffer), "%.17g", values[n]);
    out += (n ? " " : "") + std::string(buffer);
  }
  return out;
}

bool ParseNumbers(const std::string& text, std::vector<double>& values, size_t count) {
  values.clear();
  const char* p = text.c_str();
  while (true) {
    char* end = nullptr;
    const double value = std::strtod(p, &end);
    if (end == p) break;
    if (!std::isfinite(value)) return false;
    values.push_back(value);
    p = end;
  }
  for (; *p; ++p)
    if (!std::isspace(static_cast<unsigned char>(*p))) return false;
  return count == 0 ? !values.empty() : values.size() == count;
}

}  // namespace rp
