#pragma once
// IPv4 addresses and networks as a lab writes them: where the OpenIGTLink server listens
// (`--bind 192.168.10.5`, `--bind all`) and which clients may send the commands that change
// state or write files (`--command-clients 127.0.0.1,192.168.10.0/24`). Plain C++ (no sockets):
// parsing and matching only, so the PLUS configuration parser and its fuzz target use it too.
#include <cstdint>
#include <string>
#include <vector>

namespace rp {

/// An address in host byte order (127.0.0.1 is 0x7F000001).
using Ipv4 = uint32_t;

/// "192.168.10.5" (four decimal numbers 0-255, nothing else). False with `error` naming the text.
bool ParseIpv4(const std::string& text, Ipv4& address, std::string& error);
std::string FormatIpv4(Ipv4 address);

/// Where a server listens: an address of this machine, or every interface ("all", "*", "0.0.0.0").
bool ParseBindAddress(const std::string& text, Ipv4& address, std::string& error);
/// True for 127.0.0.0/8.
bool IsLoopback(Ipv4 address);

/// An address or a network in CIDR form: "192.168.10.7" (one host), "192.168.10.0/24".
struct Ipv4Network {
  Ipv4 Address = 0;  // with the host bits cleared
  int PrefixLength = 32;
  bool Contains(Ipv4 address) const;
  std::string ToString() const;
};
bool ParseIpv4Network(const std::string& text, Ipv4Network& network, std::string& error);

/// The clients allowed a privilege: a list of networks. Empty allows nobody.
class AddressAllowList {
 public:
  /// Loopback only (127.0.0.0/8): the default for commands that change state or write files.
  static AddressAllowList Loopback();
  /// Adds "a.b.c.d", "a.b.c.d/n", comma-separated lists of them, or "none" (adds nothing).
  /// False with `error` naming the item that is not one.
  bool Add(const std::string& text, std::string& error);
  bool Contains(Ipv4 address) const;
  /// "127.0.0.0/8, 192.168.10.7" ("nobody" when empty).
  std::string ToString() const;
  const std::vector<Ipv4Network>& Networks() const { return this->Items; }

 private:
  std::vector<Ipv4Network> Items;
};

}  // namespace rp
