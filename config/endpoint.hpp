#pragma once
// Addresses, ports, URLs and socket paths as the config writes them (SPEC §10), parsed once
// by the config's parse into what the daemon binds or connects to. `unima-bridge check` and the
// daemon read the same result, so check accepts exactly what the daemon can use: an
// address the socket layer would refuse ("Invalid argument" at start) is a config error
// naming file:line:column instead.
//
// Pure: no sockets, no file system (config/socket_path looks at the file system).

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <variant>

namespace unima::config {

/// A TCP endpoint as the socket layer takes it: the host without IPv6 brackets.
struct HostPort {
  std::string host;
  std::uint16_t port = 0;
  bool operator==(const HostPort&) const = default;
};

/// What a host may be. The daemon listens only on an address literal: a name would be
/// looked up once, at start, and may mean another address by the next reboot. It
/// connects to a name or an address, looked up at each connection.
enum class HostRule {
  listen_address,         // modbus.tcp.listen
  listen_address_or_any,  // unimabus.listen: `*` is every IPv4 interface
  address_or_name,        // modbus.master.tcp
};

/// Port 0 lets the kernel pick a free port where the daemon listens; where it connects
/// it means nothing.
enum class PortRule { zero_is_any_free_port, nonzero };

/// The longest unix socket path: sockaddr_un holds 108 bytes with the terminating zero.
constexpr std::size_t max_socket_path = 107;

/// Whether `text` is an IP address literal (IPv4 dotted quad, or IPv6), as the socket
/// layer takes it.
bool is_ip_address(std::string_view text);

/// nullopt when `text` is an address the daemon can listen on under `rule`; else why
/// not, for the message of the key that holds it.
std::optional<std::string> listen_address_error(std::string_view text, HostRule rule);

/// True for an address of 127.0.0.0/8 or ::1 (or 127.0.0.0/8 mapped into IPv6): reachable
/// from this machine only. For a listen address and a peer's alike.
bool is_loopback_address(std::string_view text);

/// "host:port", "[v6]:port", or an IPv6 address and port split at the last colon
/// ("::1:502"). The host follows `rule` (`*` becomes 0.0.0.0); else the reason, naming
/// `text`.
std::variant<HostPort, std::string> parse_host_port(std::string_view text, HostRule rule, PortRule port_rule);

/// nullopt when `path` can name a unix socket (1..107 bytes); else why not ("must be …").
std::optional<std::string> socket_path_error(std::string_view path);

/// unimabus.listen: `unix:/path` or `host:port` (an address or `*`, port 0 = any free).
struct ListenEndpoint {
  std::string text;       // as written, for the log
  std::string unix_path;  // set for a unix socket
  HostPort tcp;           // else this
  bool is_unix() const { return !unix_path.empty(); }
  bool operator==(const ListenEndpoint&) const = default;
};
std::variant<ListenEndpoint, std::string> parse_listen_endpoint(std::string_view text);

/// mqtt.broker (SPEC §12): mqtt://host[:port] or mqtts://host[:port], a trailing / allowed.
struct MqttBroker {
  bool tls = false;  // mqtts://
  HostPort endpoint;  // a name or an address; without a port the protocol's own, 1883 or 8883
  bool operator==(const MqttBroker&) const = default;
};
std::variant<MqttBroker, std::string> parse_mqtt_broker(std::string_view url);

}  // namespace unima::config
