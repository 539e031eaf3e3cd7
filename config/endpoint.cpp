#include "config/endpoint.hpp"

#include <arpa/inet.h>

#include <algorithm>
#include <charconv>

#include <fmt/format.h>

namespace unima::config {

namespace {

constexpr std::string_view every_interface = "0.0.0.0";

bool all_of(std::string_view text, std::string_view allowed) {
  return text.find_first_not_of(allowed) == std::string_view::npos;
}

// RFC 1123 names (letters, digits, hyphens in dot-separated labels of 1..63), and the
// underscore that some local networks use; a trailing dot is the root.
bool is_host_name(std::string_view name) {
  if (!name.empty() && name.back() == '.') name.remove_suffix(1);
  if (name.empty() || name.size() > 253) return false;
  while (true) {
    const auto dot = name.find('.');
    const auto label = name.substr(0, dot);
    if (label.empty() || label.size() > 63 || label.front() == '-' || label.back() == '-') return false;
    if (!all_of(label, "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789-_")) return false;
    if (dot == std::string_view::npos) return true;
    name.remove_prefix(dot + 1);
  }
}

std::string listen_hint(HostRule rule) {
  return fmt::format("0.0.0.0 every IPv4 interface, :: every IPv6 one, 127.0.0.1 this machine only{}",
                     rule == HostRule::listen_address_or_any ? ", * every interface" : "");
}

}  // namespace

bool is_ip_address(std::string_view text) {
  // inet_pton is what the socket layer (Asio's make_address) parses with, so an address
  // accepted here is one the daemon can bind or connect to. Asio also takes an IPv6
  // address's scope (fe80::1%eth0, the interface of a link-local address).
  const auto percent = text.find('%');
  const std::string address(text.substr(0, percent));
  unsigned char bytes[16];
  if (percent != std::string_view::npos) {
    const auto scope = text.substr(percent + 1);
    return !scope.empty() && all_of(scope, "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789._-") &&
           ::inet_pton(AF_INET6, address.c_str(), bytes) == 1;
  }
  return ::inet_pton(AF_INET, address.c_str(), bytes) == 1 || ::inet_pton(AF_INET6, address.c_str(), bytes) == 1;
}

std::optional<std::string> listen_address_error(std::string_view text, HostRule rule) {
  if (text == "*" && rule == HostRule::listen_address_or_any) return std::nullopt;
  if (is_ip_address(text)) return std::nullopt;
  // Digits and dots only would be looked up as a name and fail at each connection.
  if (!text.empty() && all_of(text, "0123456789."))
    return fmt::format("'{}' is not an IP address (IPv4 is four numbers 0..255: 192.168.1.10)", text);
  if (rule == HostRule::address_or_name) {
    if (is_host_name(text)) return std::nullopt;
    return fmt::format("'{}' is neither an IP address nor a host name", text);
  }
  if (is_host_name(text))
    return fmt::format("'{}' is a name; the daemon listens on an IP address of this machine ({})", text,
                       listen_hint(rule));
  return fmt::format("'{}' is not an IP address ({})", text, listen_hint(rule));
}

std::variant<HostPort, std::string> parse_host_port(std::string_view text, HostRule rule, PortRule port_rule) {
  std::string_view host;
  std::string_view port;
  if (text.starts_with('[')) {
    // [v6]:port, the URL way of writing an IPv6 address with a port.
    const auto close = text.find(']');
    if (close == std::string_view::npos || close + 1 >= text.size() || text[close + 1] != ':')
      return fmt::format("'{}' is not host:port", text);
    host = text.substr(1, close - 1);
    port = text.substr(close + 2);
    if (host.find(':') == std::string_view::npos || !is_ip_address(host))
      return fmt::format("'{}': brackets hold an IPv6 address, and '{}' is not one", text, host);
  } else {
    const auto colon = text.rfind(':');
    if (colon == std::string_view::npos || colon == 0) return fmt::format("'{}' is not host:port", text);
    host = text.substr(0, colon);
    port = text.substr(colon + 1);
    if (auto error = listen_address_error(host, rule)) return fmt::format("'{}': {}", text, *error);
  }
  unsigned value = 0;
  const auto [end, ec] = std::from_chars(port.data(), port.data() + port.size(), value);
  const unsigned lowest = port_rule == PortRule::nonzero ? 1 : 0;
  if (port.empty() || !all_of(port, "0123456789") || ec != std::errc{} || end != port.data() + port.size() ||
      value < lowest || value > 65535)
    return fmt::format("'{}' has no valid port ({}..65535 after the last colon)", text, lowest);
  HostPort result{std::string(host == "*" ? every_interface : host), static_cast<std::uint16_t>(value)};
  return result;
}

std::optional<std::string> socket_path_error(std::string_view path) {
  if (path.empty() || path.size() > max_socket_path || path.find('\0') != std::string_view::npos)
    return fmt::format("must be a path of 1..{} characters (a unix socket's limit)", max_socket_path);
  return std::nullopt;
}

std::variant<ListenEndpoint, std::string> parse_listen_endpoint(std::string_view text) {
  ListenEndpoint endpoint;
  endpoint.text = std::string(text);
  if (text.starts_with("unix:")) {
    const auto path = text.substr(5);
    if (path.empty()) return std::string("unix: needs a socket path, e.g. unix:/run/unima-bridge/feed.sock");
    if (auto error = socket_path_error(path)) return fmt::format("the socket path of '{}' {}", text, *error);
    endpoint.unix_path = std::string(path);
    return endpoint;
  }
  if (text.find(':') == std::string_view::npos) return fmt::format("'{}' is not host:port or unix:/path", text);
  auto tcp = parse_host_port(text, HostRule::listen_address_or_any, PortRule::zero_is_any_free_port);
  if (auto* error = std::get_if<std::string>(&tcp)) return std::move(*error);
  endpoint.tcp = std::get<HostPort>(std::move(tcp));
  return endpoint;
}

std::variant<MqttBroker, std::string> parse_mqtt_broker(std::string_view url) {
  MqttBroker broker;
  std::string_view rest = url;
  if (rest.starts_with("mqtts://")) {
    broker.tls = true;
    rest.remove_prefix(8);
  } else if (rest.starts_with("mqtt://")) {
    rest.remove_prefix(7);
  } else {
    return fmt::format("'{}' must start with mqtt:// or mqtts://", url);
  }
  if (rest.ends_with('/')) rest.remove_suffix(1);
  const bool has_port = rest.starts_with('[') ? rest.find("]:") != std::string_view::npos
                                              : std::count(rest.begin(), rest.end(), ':') == 1;
  const std::string with_port = has_port ? std::string(rest) : fmt::format("{}:{}", rest, broker.tls ? 8883 : 1883);
  auto endpoint = parse_host_port(with_port, HostRule::address_or_name, PortRule::nonzero);
  if (auto* error = std::get_if<std::string>(&endpoint)) return std::move(*error);
  broker.endpoint = std::get<HostPort>(std::move(endpoint));
  return broker;
}

bool is_loopback_address(std::string_view text) {
  const std::string address(text);
  in_addr v4{};
  if (::inet_pton(AF_INET, address.c_str(), &v4) == 1) return (ntohl(v4.s_addr) >> 24) == 127;
  in6_addr v6{};
  if (::inet_pton(AF_INET6, address.c_str(), &v6) != 1) return false;
  // ::ffff:127.0.0.1 is how a dual-stack socket names an IPv4 peer on this machine.
  return IN6_IS_ADDR_LOOPBACK(&v6) || (IN6_IS_ADDR_V4MAPPED(&v6) && v6.s6_addr[12] == 127);
}

}  // namespace unima::config
