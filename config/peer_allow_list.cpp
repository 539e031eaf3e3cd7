#include "config/peer_allow_list.hpp"

#include <arpa/inet.h>

#include <algorithm>
#include <charconv>

#include <fmt/format.h>

namespace unima::config {

namespace {

constexpr unsigned ipv4_in_ipv6 = 96;  // ::ffff:0:0/96

bool in_prefix(const PeerAddress& a, const PeerAddress& b, unsigned prefix) {
  const unsigned whole = prefix / 8;
  if (!std::equal(a.begin(), a.begin() + whole, b.begin())) return false;
  if (prefix % 8 == 0) return true;
  const auto mask = static_cast<std::uint8_t>(0xFF << (8 - prefix % 8));
  return (a[whole] & mask) == (b[whole] & mask);
}

}  // namespace

bool parse_peer_address(std::string_view text, PeerAddress& address) {
  const std::string literal(text);
  std::array<std::uint8_t, 4> v4{};
  if (::inet_pton(AF_INET, literal.c_str(), v4.data()) == 1) {
    address = {};
    address[10] = address[11] = 0xFF;
    std::copy(v4.begin(), v4.end(), address.begin() + 12);
    return true;
  }
  return ::inet_pton(AF_INET6, literal.c_str(), address.data()) == 1;
}

std::variant<NetworkRange, std::string> parse_network_range(std::string_view text) {
  NetworkRange range;
  range.text = std::string(text);
  const auto slash = text.find('/');
  const auto host = text.substr(0, slash);
  if (!parse_peer_address(host, range.address))
    return fmt::format("'{}' is not an IP address or a CIDR range (192.168.10.0/24, fd00::/8)", text);
  const bool v4 = host.find(':') == std::string_view::npos;
  const unsigned max_prefix = v4 ? 32 : 128;
  unsigned prefix = max_prefix;
  if (slash != std::string_view::npos) {
    const auto digits = text.substr(slash + 1);
    const auto [end, error] = std::from_chars(digits.data(), digits.data() + digits.size(), prefix);
    if (digits.empty() || error != std::errc{} || end != digits.data() + digits.size() || prefix > max_prefix)
      return fmt::format("'{}': the prefix length after '/' must be 0..{}", text, max_prefix);
  }
  range.prefix = v4 ? ipv4_in_ipv6 + prefix : prefix;
  PeerAddress network{};
  for (unsigned i = 0; i < 16; ++i) {
    const unsigned bits = std::min(8u, range.prefix > 8 * i ? range.prefix - 8 * i : 0u);
    network[i] = static_cast<std::uint8_t>(range.address[i] & (0xFF00 >> bits));
  }
  if (network != range.address)
    return fmt::format("'{}' has host bits set past its prefix: the range starts elsewhere", text);
  return range;
}

bool NetworkRange::contains(const PeerAddress& peer) const { return in_prefix(address, peer, prefix); }

bool PeerAllowList::allows(const PeerAddress& peer) const {
  return ranges.empty() ||
         std::any_of(ranges.begin(), ranges.end(), [&](const NetworkRange& range) { return range.contains(peer); });
}

bool PeerAllowList::operator==(const PeerAllowList& other) const {
  return std::equal(ranges.begin(), ranges.end(), other.ranges.begin(), other.ranges.end(),
                    [](const NetworkRange& a, const NetworkRange& b) { return a.address == b.address && a.prefix == b.prefix; });
}

}  // namespace unima::config
