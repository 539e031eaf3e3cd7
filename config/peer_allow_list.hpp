#pragma once
// `modbus.tcp.allow` (SPEC §11): the peers that may connect, as addresses and CIDR ranges,
// IPv4 and IPv6. An IPv4 address and the same address mapped into IPv6 (::ffff:a.b.c.d,
// what a dual-stack listener on :: sees) are one peer.
//
// Pure: the TCP adapter hands over the peer's 16 address bytes at accept.

#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace unima::config {

/// An address in IPv6 form: IPv4 as ::ffff:a.b.c.d.
using PeerAddress = std::array<std::uint8_t, 16>;

struct NetworkRange {
  PeerAddress address{};  // the host bits beyond `prefix` are zero
  unsigned prefix = 128;  // of the IPv6 form: an IPv4 /24 is /120
  std::string text;       // as written, for the log and `check`
  bool contains(const PeerAddress& peer) const;
};

/// "192.168.10.0/24", "10.1.2.3", "fd00::/8", "::1"; else why not. Host bits set past the
/// prefix (192.168.10.7/24) are an error: the writer meant something else.
std::variant<NetworkRange, std::string> parse_network_range(std::string_view text);

/// "1.2.3.4", "::ffff:1.2.3.4" and "::1" alike; false when `text` is no address.
bool parse_peer_address(std::string_view text, PeerAddress& address);

class PeerAllowList {
 public:
  /// An empty list lets every peer in: the key was not given.
  bool allows(const PeerAddress& peer) const;
  bool empty() const { return ranges.empty(); }

  std::vector<NetworkRange> ranges;
  bool operator==(const PeerAllowList& other) const;
};

}  // namespace unima::config
