// Configuration errors as a technician reads them (issue 30, point 6), through the public
// contract: `unima-bridge check --config FILE` and the daemon's start. Each message names
// file:line:column of the line that is wrong, the key, and what to do; warnings are
// `file:line:column: warning: …`, `check` still exits 0, and the daemon logs them at start.

#include <fmt/format.h>
#include <signal.h>

#include <algorithm>
#include <filesystem>
#include <string>

#include "platform/asio.hpp"
#include "tests/integration/certificate_fixture.hpp"
#include "tests/integration/cli_under_test.hpp"

namespace unima::test {
namespace {

namespace fs = std::filesystem;

class ConfigMessages : public CertificateTest {
 protected:
  /// `unima-bridge check` on `yaml`, written to bridge.yaml.
  CommandResult check(const std::string& yaml) const {
    test_support::write_file(file(), yaml);
    return run(bridge_cli() + " check --config " + file());
  }
  std::string file() const { return (dir.path() / "bridge.yaml").string(); }
  /// The daemon started on `yaml` exits 1 and its log holds `must_log`.
  void expect_refused_start(const std::string& yaml, const std::string& must_log) {
    daemon = std::make_unique<Daemon>(dir, yaml);
    ASSERT_TRUE(eventually([&] { return !daemon->running(); })) << daemon->log();
    EXPECT_EQ(daemon->exit_code(), 1) << daemon->log();
    EXPECT_NE(daemon->log().find(must_log), std::string::npos) << daemon->log();
  }
  /// The test's usual config with `section` as the body of modbus (after its address).
  std::string with_modbus(const std::string& section) {
    config.modbus_extra = section;
    return config.yaml();
  }
};

TEST_F(ConfigMessages, ATabIndentingALineIsNamedAtThatLine) {
  // Line 1..: unimabus (4 lines), modbus:, address, tcp; the tab on the line after tcp.
  const auto yaml = with_modbus("  rtu:\n    device: /dev/null\n\tbaud: 9600\n");
  const auto line = std::to_string(std::count(yaml.begin(), yaml.begin() + static_cast<long>(yaml.find('\t')), '\n') + 1);
  const auto result = check(yaml);
  EXPECT_EQ(result.status, 1) << result.output;
  const auto expected = ":" + line + ":1: a tab indents this line; YAML indents with spaces";
  EXPECT_NE(result.output.find(file() + expected), std::string::npos) << result.output;
  expect_refused_start(yaml, expected);
}

TEST_F(ConfigMessages, ALineIndentedUnlikeItsSiblingsSaysWhereItSeemsToBelong) {
  const auto yaml = with_modbus("  rtu:\n    device: /dev/null\n   baud: 9600\n");
  const auto line = std::to_string(std::count(yaml.begin(), yaml.begin() + static_cast<long>(yaml.find("   baud")), '\n') + 1);
  const auto result = check(yaml);
  EXPECT_EQ(result.status, 1) << result.output;
  EXPECT_NE(result.output.find(file() + ":" + line + ":4: this line is indented by 3 spaces: the keys of 'rtu' above it "
                               "by 4 ('device' on line " + std::to_string(std::stoi(line) - 1) + "), those of 'modbus' by "
                               "2; it seems to belong to 'rtu': indent it by 4 spaces"),
            std::string::npos)
      << result.output;
  expect_refused_start(yaml, ":" + line + ":4: this line is indented by 3 spaces");
}

// Issue 44, finding 1: the installed config with a `modbus: { rtu: … }` block pasted at its
// end gave a TCP-only bridge, `check` saying OK. Both refuse it, naming both positions.
TEST_F(ConfigMessages, ASectionWrittenTwiceIsRefusedByCheckAndTheDaemonNamingBoth) {
  const auto yaml = config.yaml() + "modbus:\n  rtu: { device: /dev/null }\n";
  const auto count_lines = [&](std::size_t end) {
    return std::count(yaml.begin(), yaml.begin() + static_cast<long>(end), '\n') + 1;
  };
  const auto first = count_lines(yaml.find("modbus:"));
  const auto second = count_lines(yaml.rfind("modbus:"));
  ASSERT_LT(first, second);
  const auto expected = fmt::format(":{}:1: 'modbus' is written twice in this mapping (first at line {}, column 1); "
                                    "only one would count: merge the two", second, first);
  const auto result = check(yaml);
  EXPECT_EQ(result.status, 1) << result.output;
  EXPECT_NE(result.output.find(file() + expected), std::string::npos) << result.output;
  expect_refused_start(yaml, expected);
}

// Issue 44, finding 2: `check` and the daemon agree on the files a config names. A missing
// MQTT password file is refused by both at its key (the daemon said "cannot be read", no
// line, no reason); a state file in a directory that is not there is a warning in both,
// and the daemon makes the directory (it exited without key or line).
TEST_F(ConfigMessages, CheckAndTheDaemonAgreeOnAMissingPasswordFileAndAMissingStateDirectory) {
  const auto password = (dir.path() / "mqtt.pass").string();
  config.extra = "mqtt:\n  broker: 'mqtt://127.0.0.1:1'\n  username: site\n  password_file: " + password + "\n";
  auto yaml = config.yaml();
  const auto line = std::count(yaml.begin(), yaml.begin() + static_cast<long>(yaml.find("  password_file:")), '\n') + 1;
  const auto refused = fmt::format(":{}:18: mqtt.password_file: {}: no such file: correct the path, or put the file there",
                                   line, password);
  auto result = check(yaml);
  EXPECT_EQ(result.status, 1) << result.output;
  EXPECT_NE(result.output.find(file() + refused), std::string::npos) << result.output;
  expect_refused_start(yaml, refused);

  const auto typo = dir.path() / "unima-brige";
  config.extra = "state:\n  file: " + (typo / "state").string() + "\n";
  yaml = config.yaml();
  const auto warned = fmt::format("state.file: {}: the directory {} is not there; the daemon makes it at start",
                                  (typo / "state").string(), typo.string());
  result = check(yaml);
  EXPECT_EQ(result.status, 0) << result.output;
  EXPECT_NE(result.output.find(warned), std::string::npos) << result.output;
  test_support::write_file(file(), yaml);
  daemon = std::make_unique<Daemon>(dir, yaml);
  ASSERT_TRUE(wait_for_port(config.modbus_port)) << daemon->log();
  // The port listens before the bridge starts and says its warnings: wait for the line.
  EXPECT_TRUE(eventually([&] { return daemon->log().find(warned) != std::string::npos; })) << daemon->log();
  EXPECT_TRUE(eventually([&] { return fs::is_regular_file(typo / "state"); })) << daemon->log();
}

// Issue 44, finding 2: a ':' left out gave yaml-cpp's "illegal map value" one line late.
TEST_F(ConfigMessages, AKeyWithoutItsColonIsNamedAtItsOwnLineByCheckAndTheDaemon) {
  const auto yaml = with_modbus("  mode slave\n  rtu: { device: /dev/null }\n");
  const auto line = std::count(yaml.begin(), yaml.begin() + static_cast<long>(yaml.find("  mode slave")), '\n') + 1;
  const auto expected = fmt::format(":{}:3: this line has no ':' after its key, unlike 'rtu' on line {}: write 'mode: slave'",
                                    line, line + 1);
  const auto result = check(yaml);
  EXPECT_EQ(result.status, 1) << result.output;
  EXPECT_NE(result.output.find(file() + expected), std::string::npos) << result.output;
  expect_refused_start(yaml, expected);
}

TEST_F(ConfigMessages, EveryPemKeyIsCheckedAtItsLineSayingWhatIsWrong) {
  const auto tls = [&](const std::string& certificate, const std::string& key) {
    return with_modbus("  tls:\n    port: " + std::to_string(free_port()) + "\n    certificate: " + certificate +
                       "\n    key: " + key + "\n    ca: " + pem("ca.pem") + "\n");
  };
  const auto key_line = [](const std::string& yaml) {
    return std::to_string(std::count(yaml.begin(), yaml.begin() + static_cast<long>(yaml.find("    key: ")), '\n') + 1);
  };
  // A key file that is not there: which key, which file, what is wrong and what to do.
  auto yaml = tls(pem("server.pem"), pem("gone.key"));
  auto result = check(yaml);
  EXPECT_EQ(result.status, 1) << result.output;
  const auto missing = ":" + key_line(yaml) + ":10: modbus.tls.key: " + pem("gone.key") +
                       ": no such file: correct the path, or put the file there";
  EXPECT_NE(result.output.find(file() + missing), std::string::npos) << result.output;
  expect_refused_start(yaml, missing);
  // The certificate given as the key.
  yaml = tls(pem("server.pem"), pem("server.pem"));
  result = check(yaml);
  EXPECT_NE(result.output.find(":" + key_line(yaml) + ":10: modbus.tls.key: " + pem("server.pem") +
                               ": a certificate, not a private key: are the certificate and key files swapped?"),
            std::string::npos)
      << result.output;
  // A key of another certificate.
  yaml = tls(pem("server.pem"), pem("viewer.key"));
  result = check(yaml);
  EXPECT_NE(result.output.find(":" + key_line(yaml) + ":10: modbus.tls.key: " + pem("viewer.key") +
                               ": this key does not belong to the certificate of modbus.tls.certificate (" +
                               pem("server.pem") + ")"),
            std::string::npos)
      << result.output;
  // Garbage as the certificate, at the certificate's line.
  test_support::write_file(certs / "garbage.pem", "-----BEGIN CERTIFICATE-----\nnot base64\n");
  yaml = tls(pem("garbage.pem"), pem("server.key"));
  result = check(yaml);
  EXPECT_NE(result.output.find(":" + std::to_string(std::stoi(key_line(yaml)) - 1) + ":18: modbus.tls.certificate: " +
                               pem("garbage.pem") + ": not a PEM certificate"),
            std::string::npos)
      << result.output;
  // http.tls and mqtt name theirs the same way.
  config.extra = "http:\n  port: " + std::to_string(free_port()) + "\n  tls:\n    certificate: " + pem("server.pem") +
                 "\n    key: " + pem("ca.key") + "\n";
  result = check(with_modbus(""));
  EXPECT_NE(result.output.find(": http.tls.key: " + pem("ca.key") + ": this key does not belong to the certificate of "
                               "http.tls.certificate"),
            std::string::npos)
      << result.output;
  config.extra = "mqtt:\n  broker: mqtts://127.0.0.1:1\n  ca: " + pem("gone.pem") + "\n";
  result = check(with_modbus(""));
  EXPECT_NE(result.output.find(": mqtt.ca: " + pem("gone.pem") + ": no such file"), std::string::npos) << result.output;
}

TEST_F(ConfigMessages, APlcStyleRegisterNumberIsAWarningSayingWhatWasProbablyMeant) {
  config.blocks = "  - { type: read, register: 40001, source: D1+0x01 }\n";
  const auto yaml = config.yaml();
  const auto line = std::to_string(std::count(yaml.begin(), yaml.begin() + static_cast<long>(yaml.find("40001")), '\n') + 1);
  const auto result = check(yaml);
  EXPECT_EQ(result.status, 0) << result.output;
  const auto warning = ":" + line + ":29: warning: register 40001 is taken as address 0x9C41; if holding register 40001 "
                       "(PLC numbering, from 1) was meant, write its address 0x0000";
  EXPECT_NE(result.output.find(file() + warning), std::string::npos) << result.output;
  start();
  EXPECT_TRUE(daemon->wait_for_log(warning)) << daemon->log();
}

TEST_F(ConfigMessages, ASerialDeviceThatIsNotThereIsAWarningNamingTheRetry) {
  const auto yaml = with_modbus("  rtu: { device: " + (dir.path() / "ttyUSB9").string() + " }\n");
  const auto result = check(yaml);
  EXPECT_EQ(result.status, 0) << result.output;
  EXPECT_NE(result.output.find(": warning: modbus.rtu.device: " + (dir.path() / "ttyUSB9").string() +
                               ": no such device; the daemon starts without it and tries to open it again every 5 s"),
            std::string::npos)
      << result.output;
}

// Issue 40: a user remote_config.http lets PUT a config must be in the users file, or the
// name is a typo that would lock that user out; `check` refuses it at remote_config.http,
// naming the user and the file, as the daemon's remote changes do (check/).
TEST_F(ConfigMessages, CheckRefusesARemoteHttpUserWhoIsNotInTheUsersFile) {
  const auto users = (dir.path() / "http.users").string();
  // openssl passwd -6 -salt salzsalz secret
  test_support::write_file(users, "alice:$6$salzsalz$T6JPgc5oSlQmLkWq.mzSbtz8riZYp5RKogAdkAMphpHutqbzTWM.R2hHZXzRwqaHTGP"
                                  "bckcwMimHDhrrzvUs40\n");
  const auto with_remote_users = [&](const std::string& listed) {
    config.extra = "http:\n  listen: 127.0.0.1\n  port: " + std::to_string(free_port()) + "\n  users: " + users +
                   "\nremote_config:\n  http: " + listed + "\n";
    return with_modbus("");
  };
  auto yaml = with_remote_users("[alice, alcie]");
  const auto line = std::count(yaml.begin(), yaml.begin() + static_cast<long>(yaml.find("  http: [")), '\n') + 1;
  auto result = check(yaml);
  EXPECT_EQ(result.status, 1) << result.output;
  EXPECT_NE(result.output.find(fmt::format("{}:{}:9: remote_config.http: 'alcie' is not a user of http.users ({}): add "
                                           "the user to that file, or take the name out of the list",
                                           file(), line, users)),
            std::string::npos)
      << result.output;
  EXPECT_EQ(result.output.find(": OK"), std::string::npos) << result.output;

  result = check(with_remote_users("[alice]"));
  EXPECT_EQ(result.status, 0) << result.output;
  EXPECT_NE(result.output.find(file() + ": OK"), std::string::npos) << result.output;
}

// Another program holds the port: the error names the key, its line and the address.
TEST_F(ConfigMessages, APortInUseAtStartNamesTheKeyAndTheAddress) {
  asio::io_context io;
  const auto hold = [&](std::uint16_t port) {
    return asio::ip::tcp::acceptor(io, asio::ip::tcp::endpoint(asio::ip::make_address("127.0.0.1"), port));
  };
  {
    auto holder = hold(config.modbus_port);
    const auto port = std::to_string(config.modbus_port);
    expect_refused_start(config.yaml(), ":7:35: modbus.tcp.port " + port + ": address 127.0.0.1:" + port +
                                            " is in use by another program");
  }
  {
    const auto tls_port = free_port();
    auto holder = hold(tls_port);
    const auto port = std::to_string(tls_port);
    expect_refused_start(with_modbus(tls_section(tls_port, "{}")),
                         ": modbus.tls.port " + port + ": address 127.0.0.1:" + port + " is in use by another program");
  }
  {
    const auto http_port = free_port();
    auto holder = hold(http_port);
    const auto port = std::to_string(http_port);
    config.extra = "http:\n  listen: 127.0.0.1\n  port: " + port + "\n";
    expect_refused_start(with_modbus(""), ": http.port " + port + ": address 127.0.0.1:" + port +
                                              " is in use by another program");
  }
}

}  // namespace
}  // namespace unima::test
