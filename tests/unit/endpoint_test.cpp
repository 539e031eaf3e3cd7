// Addresses, ports and socket paths (SPEC §10, issue 17 item 5): one parse for `unima-bridge
// check` and the daemon, so that check accepts exactly what the daemon can bind or connect
// to, and every refusal names file:line:column.

#include <gtest/gtest.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <filesystem>
#include <string>

#include "config/config.hpp"
#include "config/endpoint.hpp"
#include "config/socket_path.hpp"
#include "tests/support/error_message.hpp"
#include "tests/support/temp_files.hpp"

namespace unima::config {
namespace {

using test_support::TempDir;

std::string error_of(const std::string& yaml) {
  return test_support::error_message<ConfigError>([&] { (void)load_text(yaml, "bridge.yaml"); });
}
std::string feed(const std::string& listen) {
  return "unimabus:\n  transport: feed\n  listen: " + listen + "\n";
}
std::string tcp_listen(const std::string& address) { return "modbus:\n  tcp: { listen: " + address + " }\n"; }
std::string master_tcp(const std::string& target) { return "modbus:\n  mode: master\n  master: { tcp: " + target + " }\n"; }

bool mentions(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

TEST(IpAddress, IsWhatTheSocketLayerTakes) {
  EXPECT_TRUE(is_ip_address("127.0.0.1"));
  EXPECT_TRUE(is_ip_address("0.0.0.0"));
  EXPECT_TRUE(is_ip_address("::"));
  EXPECT_TRUE(is_ip_address("fe80::1"));
  EXPECT_TRUE(is_ip_address("::ffff:10.0.0.1"));
  EXPECT_TRUE(is_ip_address("fe80::1%eth0"));  // a link-local address names its interface
  EXPECT_FALSE(is_ip_address("10.0.0.1%eth0"));
  EXPECT_FALSE(is_ip_address("fe80::1%"));
  EXPECT_FALSE(is_ip_address("999.1.1.1"));
  EXPECT_FALSE(is_ip_address("1.2.3"));
  EXPECT_FALSE(is_ip_address("localhost"));
  EXPECT_FALSE(is_ip_address(""));
  EXPECT_FALSE(is_ip_address("*"));
  EXPECT_FALSE(is_ip_address(" 127.0.0.1"));
}

// Reachable from this machine only: a listen address, or a peer as a dual-stack socket names it.
TEST(LoopbackAddress, IsThisMachineOnlyWhateverTheFamily) {
  for (const char* loopback : {"127.0.0.1", "127.3.2.1", "::1", "::ffff:127.0.0.1"})
    EXPECT_TRUE(config::is_loopback_address(loopback)) << loopback;
  for (const char* other : {"0.0.0.0", "10.0.0.1", "::", "::ffff:10.0.0.1", "fe80::1", "localhost", ""})
    EXPECT_FALSE(config::is_loopback_address(other)) << other;
}

TEST(HostPort, SplitsAtTheLastColonOrAfterBrackets) {
  using Result = std::variant<HostPort, std::string>;
  EXPECT_EQ(parse_host_port("127.0.0.1:502", HostRule::listen_address, PortRule::nonzero),
            Result(HostPort{"127.0.0.1", 502}));
  EXPECT_EQ(parse_host_port("::1:1502", HostRule::listen_address, PortRule::nonzero), Result(HostPort{"::1", 1502}));
  EXPECT_EQ(parse_host_port("[::1]:1502", HostRule::listen_address, PortRule::nonzero), Result(HostPort{"::1", 1502}));
  EXPECT_EQ(parse_host_port("*:7700", HostRule::listen_address_or_any, PortRule::nonzero),
            Result(HostPort{"0.0.0.0", 7700}));
  EXPECT_EQ(parse_host_port("plc-7.site.local:502", HostRule::address_or_name, PortRule::nonzero),
            Result(HostPort{"plc-7.site.local", 502}));
  EXPECT_EQ(parse_host_port("127.0.0.1:0", HostRule::listen_address, PortRule::zero_is_any_free_port),
            Result(HostPort{"127.0.0.1", 0}));
}

TEST(HostPort, RefusesWhatTheDaemonCouldNotUse) {
  const auto error = [](std::string_view text, HostRule rule, PortRule port = PortRule::nonzero) {
    const auto parsed = parse_host_port(text, rule, port);
    return std::holds_alternative<std::string>(parsed) ? std::get<std::string>(parsed) : "(parsed)";
  };
  EXPECT_EQ(error("localhost:5000", HostRule::listen_address_or_any),
            "'localhost:5000': 'localhost' is a name; the daemon listens on an IP address of this machine "
            "(0.0.0.0 every IPv4 interface, :: every IPv6 one, 127.0.0.1 this machine only, * every interface)");
  EXPECT_EQ(error("999.1.1.1:502", HostRule::address_or_name),
            "'999.1.1.1:502': '999.1.1.1' is not an IP address (IPv4 is four numbers 0..255: 192.168.1.10)");
  EXPECT_EQ(error("*:502", HostRule::listen_address).substr(0, 25), "'*:502': '*' is not an IP");
  EXPECT_EQ(error("*:502", HostRule::address_or_name), "'*:502': '*' is neither an IP address nor a host name");
  EXPECT_EQ(error("bad host:502", HostRule::address_or_name),
            "'bad host:502': 'bad host' is neither an IP address nor a host name");
  EXPECT_EQ(error("-x:502", HostRule::address_or_name), "'-x:502': '-x' is neither an IP address nor a host name");
  EXPECT_EQ(error("10.0.0.7", HostRule::address_or_name), "'10.0.0.7' is not host:port");
  EXPECT_EQ(error(":502", HostRule::address_or_name), "':502' is not host:port");
  EXPECT_EQ(error("[::1:502", HostRule::address_or_name), "'[::1:502' is not host:port");
  EXPECT_EQ(error("[10.0.0.1]:502", HostRule::address_or_name),
            "'[10.0.0.1]:502': brackets hold an IPv6 address, and '10.0.0.1' is not one");
  EXPECT_EQ(error("10.0.0.7:", HostRule::address_or_name), "'10.0.0.7:' has no valid port (1..65535 after the last colon)");
  EXPECT_EQ(error("10.0.0.7:0", HostRule::address_or_name), "'10.0.0.7:0' has no valid port (1..65535 after the last colon)");
  EXPECT_EQ(error("10.0.0.7:65536", HostRule::address_or_name, PortRule::zero_is_any_free_port),
            "'10.0.0.7:65536' has no valid port (0..65535 after the last colon)");
  EXPECT_EQ(error("10.0.0.7:+5", HostRule::address_or_name), "'10.0.0.7:+5' has no valid port (1..65535 after the last colon)");
  EXPECT_EQ(error("10.0.0.7:99999999999", HostRule::address_or_name),
            "'10.0.0.7:99999999999' has no valid port (1..65535 after the last colon)");
}

TEST(ListenEndpoint, IsAUnixPathOrHostAndPort) {
  const auto unix = std::get<ListenEndpoint>(parse_listen_endpoint("unix:/run/unima-bridge/feed.sock"));
  EXPECT_TRUE(unix.is_unix());
  EXPECT_EQ(unix.unix_path, "/run/unima-bridge/feed.sock");
  EXPECT_EQ(unix.text, "unix:/run/unima-bridge/feed.sock");
  const auto tcp = std::get<ListenEndpoint>(parse_listen_endpoint("*:7700"));
  EXPECT_FALSE(tcp.is_unix());
  EXPECT_EQ(tcp.tcp, (HostPort{"0.0.0.0", 7700}));
  EXPECT_EQ(std::get<std::string>(parse_listen_endpoint("unix:")),
            "unix: needs a socket path, e.g. unix:/run/unima-bridge/feed.sock");
  EXPECT_EQ(std::get<std::string>(parse_listen_endpoint("unix:/" + std::string(107, 'a'))),
            "the socket path of 'unix:/" + std::string(107, 'a') +
                "' must be a path of 1..107 characters (a unix socket's limit)");
  EXPECT_EQ(std::get<std::string>(parse_listen_endpoint("7700")), "'7700' is not host:port or unix:/path");
}

// The two that passed `check` and stopped the daemon with a bare "Invalid argument".
TEST(ConfigEndpoints, NamesAndBadAddressesAreRefusedWithTheirPosition) {
  EXPECT_EQ(error_of(feed("localhost:5000")),
            "bridge.yaml:3:11: 'localhost:5000': 'localhost' is a name; the daemon listens on an IP address of this "
            "machine (0.0.0.0 every IPv4 interface, :: every IPv6 one, 127.0.0.1 this machine only, * every interface)");
  EXPECT_EQ(error_of(tcp_listen("999.1.1.1")),
            "bridge.yaml:2:18: '999.1.1.1' is not an IP address (IPv4 is four numbers 0..255: 192.168.1.10)");
  EXPECT_EQ(error_of(tcp_listen("localhost")),
            "bridge.yaml:2:18: 'localhost' is a name; the daemon listens on an IP address of this machine (0.0.0.0 "
            "every IPv4 interface, :: every IPv6 one, 127.0.0.1 this machine only)");
  // `*` is the feed's way of saying every interface; modbus.tcp.listen takes an address.
  EXPECT_TRUE(mentions(error_of(tcp_listen("'*'")), "bridge.yaml:2:18: '*' is not an IP address")) << error_of(tcp_listen("'*'"));
  EXPECT_EQ(error_of(master_tcp("999.1.1.1:502")),
            "bridge.yaml:3:18: '999.1.1.1:502': '999.1.1.1' is not an IP address (IPv4 is four numbers 0..255: "
            "192.168.1.10)");
  EXPECT_EQ(error_of(master_tcp("10.0.0.7:0")), "bridge.yaml:3:18: '10.0.0.7:0' has no valid port (1..65535 after the last colon)");
  EXPECT_EQ(error_of(feed("127.0.0.1:70000")),
            "bridge.yaml:3:11: '127.0.0.1:70000' has no valid port (0..65535 after the last colon)");
  EXPECT_EQ(error_of(feed("unix:/" + std::string(110, 's'))),
            "bridge.yaml:3:11: the socket path of 'unix:/" + std::string(110, 's') +
                "' must be a path of 1..107 characters (a unix socket's limit)");
}

TEST(MqttBroker, IsASchemeAHostAndAnOptionalPort) {
  using Result = std::variant<MqttBroker, std::string>;
  EXPECT_EQ(parse_mqtt_broker("mqtt://10.0.0.2"), Result(MqttBroker{false, {"10.0.0.2", 1883}}));
  EXPECT_EQ(parse_mqtt_broker("mqtts://broker.example"), Result(MqttBroker{true, {"broker.example", 8883}}));
  EXPECT_EQ(parse_mqtt_broker("mqtts://broker.example:9883/"), Result(MqttBroker{true, {"broker.example", 9883}}));
  EXPECT_EQ(parse_mqtt_broker("mqtt://[::1]:1884"), Result(MqttBroker{false, {"::1", 1884}}));
  EXPECT_EQ(parse_mqtt_broker("mqtt://::1"), Result(MqttBroker{false, {"::1", 1883}}));  // IPv6 without a port
  EXPECT_EQ(std::get<std::string>(parse_mqtt_broker("tcp://x")), "'tcp://x' must start with mqtt:// or mqtts://");
  EXPECT_EQ(std::get<std::string>(parse_mqtt_broker("mqtt://x:0")), "'x:0' has no valid port (1..65535 after the last colon)");
  EXPECT_EQ(std::get<std::string>(parse_mqtt_broker("mqtt://bad_host!:1883")),
            "'bad_host!:1883': 'bad_host!' is neither an IP address nor a host name");
}

// One check of a listen address and one of a server's PEM files, whichever section.
TEST(ConfigEndpoints, EveryServerSectionRefusesANameAndAMissingPemAlike) {
  const std::string name_refused = "'localhost' is a name; the daemon listens on an IP address of this machine (0.0.0.0 "
                                   "every IPv4 interface, :: every IPv6 one, 127.0.0.1 this machine only)";
  EXPECT_EQ(error_of("modbus:\n  tcp: { listen: localhost }\n"), "bridge.yaml:2:18: " + name_refused);
  EXPECT_EQ(error_of("modbus:\n  tls: { listen: localhost }\n"), "bridge.yaml:2:18: " + name_refused);
  EXPECT_EQ(error_of("http:\n  listen: localhost\n"), "bridge.yaml:2:11: " + name_refused);
  EXPECT_EQ(error_of("modbus:\n  tls: { certificate: c.pem, ca: ca.pem }\n"),
            "bridge.yaml:2:8: modbus.tls needs 'key', a PEM file");
  EXPECT_EQ(error_of("http:\n  tls: { certificate: c.pem }\n"), "bridge.yaml:2:8: http.tls needs 'key', a PEM file");
  EXPECT_EQ(error_of("modbus:\n  tls: { certificate: '', key: k.pem, ca: ca.pem }\n"),
            "bridge.yaml:2:23: modbus.tls.certificate must be the path of a PEM file");
  EXPECT_EQ(error_of("http:\n  tls: { certificate: '', key: k.pem }\n"),
            "bridge.yaml:2:23: http.tls.certificate must be the path of a PEM file");
}

TEST(ConfigEndpoints, TheDaemonGetsWhatTheLoaderParsed) {
  const auto feed_config = load_text(feed("'*:7700'"), "bridge.yaml");
  EXPECT_EQ(feed_config.unimabus.listen, "*:7700");
  EXPECT_EQ(feed_config.unimabus.listen_at.tcp, (HostPort{"0.0.0.0", 7700}));
  const auto unix_config = load_text(feed("unix:/run/x/feed.sock"), "bridge.yaml");
  EXPECT_EQ(unix_config.unimabus.listen_at.unix_path, "/run/x/feed.sock");
  EXPECT_EQ(load_text(tcp_listen("'::'"), "bridge.yaml").modbus.tcp->listen, "::");
  const auto master = load_text(master_tcp("'[fd00::7]:1502'"), "bridge.yaml");
  EXPECT_EQ(master.modbus.master.tcp, "[fd00::7]:1502");
  EXPECT_EQ(master.modbus.master.tcp_target, (HostPort{"fd00::7", 1502}));
  EXPECT_EQ(load_text(master_tcp("plc.local:502"), "bridge.yaml").modbus.master.tcp_target, (HostPort{"plc.local", 502}));
}

// A unix socket bound at `path`, left behind as a crashed daemon leaves it.
void leave_socket_file(const std::filesystem::path& path) {
  const int fd = ::socket(AF_UNIX, SOCK_STREAM, 0);
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  std::snprintf(address.sun_path, sizeof address.sun_path, "%s", path.c_str());
  ASSERT_EQ(::bind(fd, reinterpret_cast<sockaddr*>(&address), sizeof address), 0) << path;
  ::close(fd);
}

TEST(SocketPath, OnlyASocketIsEverRemoved) {
  TempDir dir;
  const auto file = dir.path() / "file";
  test_support::write_file(file, "precious");
  const auto link = dir.path() / "link";
  std::filesystem::create_symlink(file, link);
  const auto directory = dir.path() / "directory";
  std::filesystem::create_directory(directory);
  const auto stale = dir.path() / "stale.sock";
  leave_socket_file(stale);

  EXPECT_EQ(socket_path_conflict(file.string()),
            file.string() + " names a regular file, not a socket; the daemon never removes it to listen there");
  EXPECT_TRUE(mentions(*socket_path_conflict(link.string()), "names a symbolic link, not a socket"));
  EXPECT_TRUE(mentions(*socket_path_conflict(directory.string()), "names a directory, not a socket"));
  EXPECT_FALSE(socket_path_conflict(stale.string()));
  EXPECT_FALSE(socket_path_conflict((dir.path() / "nothing").string()));

  for (const auto& path : {file, link, directory}) {
    EXPECT_EQ(test_support::error_message<PathRefused>([&] { clear_socket_path(path.string(), "status.socket"); }),
              "status.socket: " + *socket_path_conflict(path.string()));
    remove_socket_file(path.string());
    EXPECT_TRUE(std::filesystem::exists(std::filesystem::symlink_status(path))) << path;
  }
  EXPECT_EQ(test_support::read_file(file), "precious");
  clear_socket_path(stale.string(), "status.socket");
  EXPECT_FALSE(std::filesystem::exists(std::filesystem::symlink_status(stale)));
  leave_socket_file(stale);
  remove_socket_file(stale.string());
  EXPECT_FALSE(std::filesystem::exists(std::filesystem::symlink_status(stale)));
}

TEST(ConfigPaths, ASocketPathNamingSomethingElseIsAnErrorNamingTheKey) {
  TempDir dir;
  const auto file = (dir.path() / "control.sock").string();
  test_support::write_file(file, "precious");
  EXPECT_EQ(error_of("status:\n  socket: " + file + "\n"),
            "bridge.yaml:2:11: status.socket: " + file +
                " names a regular file, not a socket; the daemon never removes it to listen there");
  EXPECT_EQ(error_of(feed("unix:" + file)),
            "bridge.yaml:3:11: unimabus.listen: " + file +
                " names a regular file, not a socket; the daemon never removes it to listen there");
  EXPECT_EQ(test_support::read_file(file), "precious");
  const auto stale = dir.path() / "stale.sock";
  leave_socket_file(stale);
  EXPECT_NO_THROW((void)load_text("status:\n  socket: " + stale.string() + "\n", "bridge.yaml"));
}

}  // namespace
}  // namespace unima::config
