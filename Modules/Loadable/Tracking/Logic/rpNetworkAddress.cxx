#include "rpNetworkAddress.h"

#include <cctype>

#include "rpStrings.h"

namespace rp {

namespace {
// A decimal number of at most `digits` digits, no sign, no leading '+'; false otherwise.
bool ParseSmallNumber(const std::string& text, size_t digits, unsigned& value) {
  if (text.empty() || text.size() > digits) return false;
  value = 0;
  for (char c : text) {
    if (c < '0' || c > '9') return false;
    value = value * 10 + static_cast<unsigned>(c - '0');
  }
  return true;
}

Ipv4 Mask(int prefixLength) { return prefixLength <= 0 ? 0u : ~Ipv4{0} << (32 - prefixLength); }
}  // namespace

bool ParseIpv4(const std::string& text, Ipv4& address, std::string& error) {
  Ipv4 value = 0;
  size_t at = 0;
  for (int part = 0; part < 4; ++part) {
    const size_t dot = part < 3 ? text.find('.', at) : text.size();
    unsigned number = 0;
    if (dot == std::string::npos || !ParseSmallNumber(text.substr(at, dot - at), 3, number) || number > 255) {
      error = "'" + text + "' is not an IPv4 address (four numbers 0-255 separated by dots, e.g. 192.168.10.5)";
      return false;
    }
    value = (value << 8) | number;
    at = dot + 1;
  }
  address = value;
  return true;
}

std::string FormatIpv4(Ipv4 a) {
  return std::to_string(a >> 24) + "." + std::to_string((a >> 16) & 255) + "." + std::to_string((a >> 8) & 255) + "." +
         std::to_string(a & 255);
}

bool ParseBindAddress(const std::string& text, Ipv4& address, std::string& error) {
  const std::string t = Trim(text);
  if (t == "all" || t == "*") {
    address = 0;
    return true;
  }
  if (!ParseIpv4(t, address, error)) {
    error += "; to listen on every interface give 'all' (0.0.0.0)";
    return false;
  }
  return true;
}

bool IsLoopback(Ipv4 address) { return (address >> 24) == 127; }

bool Ipv4Network::Contains(Ipv4 address) const { return (address & Mask(this->PrefixLength)) == this->Address; }

std::string Ipv4Network::ToString() const {
  return FormatIpv4(this->Address) + (this->PrefixLength == 32 ? "" : "/" + std::to_string(this->PrefixLength));
}

bool ParseIpv4Network(const std::string& text, Ipv4Network& network, std::string& error) {
  const std::string t = Trim(text);
  const size_t slash = t.find('/');
  unsigned prefix = 32;
  if (slash != std::string::npos && (!ParseSmallNumber(t.substr(slash + 1), 2, prefix) || prefix > 32)) {
    error = "'" + t + "': the prefix length after '/' must be 0 to 32 (192.168.10.0/24)";
    return false;
  }
  Ipv4 address = 0;
  if (!ParseIpv4(t.substr(0, slash), address, error)) return false;
  network.PrefixLength = static_cast<int>(prefix);
  network.Address = address & Mask(network.PrefixLength);
  return true;
}

AddressAllowList AddressAllowList::Loopback() {
  AddressAllowList list;
  list.Items.push_back({0x7F000000u, 8});
  return list;
}

bool AddressAllowList::Add(const std::string& text, std::string& error) {
  size_t at = 0;
  std::vector<Ipv4Network> added;
  while (at <= text.size()) {
    size_t comma = text.find(',', at);
    if (comma == std::string::npos) comma = text.size();
    const std::string item = Trim(text.substr(at, comma - at));
    at = comma + 1;
    if (item == "none") continue;
    Ipv4Network network;
    if (!ParseIpv4Network(item, network, error)) return false;
    added.push_back(network);
  }
  this->Items.insert(this->Items.end(), added.begin(), added.end());
  return true;
}

bool AddressAllowList::Contains(Ipv4 address) const {
  for (const Ipv4Network& n : this->Items)
    if (n.Contains(address)) return true;
  return false;
}

std::string AddressAllowList::ToString() const {
  std::string text;
  for (const Ipv4Network& n : this->Items) text += (text.empty() ? "" : ", ") + n.ToString();
  return text.empty() ? "nobody" : text;
}

}  // namespace rp
