// Text from outside in the log and the monitor (SPEC §10: logs cannot be flooded or forged
// from outside; issue 29, rows 5 and 6): a client certificate's role holding a newline,
// an MQTT command's payload ending in one, a feed client that connects and disconnects in
// a loop. Every line of the log and of the monitor file is the daemon's own: it starts
// with the daemon's time stamp, and the peer's text stands escaped inside it.

#include <unistd.h>

#include <filesystem>
#include <functional>
#include <regex>
#include <sstream>

#include "tests/integration/certificate_fixture.hpp"
#include "tests/support/peers/mqtt_broker.hpp"
#include "tests/support/peers/mqtt_subscription.hpp"

namespace unima::test {
namespace {

using test_support::Broker;
using test_support::payloads;
using test_support::publish;
using test_support::Subscription;

// "2026-11-27T04:01:42.221 info …" (the log when stderr is not the journal).
const std::regex log_line_start(R"(^\d{4}-\d\d-\d\dT\d\d:\d\d:\d\d\.\d{3} (trace|debug|info|warning|error|critical) )");
// "2026-11-27T04:01:42.221123Z tls:…" (a text monitor line).
const std::regex monitor_line_start(R"(^\d{4}-\d\d-\d\dT\d\d:\d\d:\d\d\.\d{6}Z )");

/// The lines of `text` that do not start as the daemon starts its lines: forged ones.
std::vector<std::string> forged_lines(const std::string& text, const std::regex& start) {
  std::vector<std::string> forged;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);)
    if (!std::regex_search(line, start)) forged.push_back(line);
  return forged;
}

using OutsideText = CertificateTest;

// Row 5: the role is the UTF8String "viewer\nFORGED line from a certificate"
// (tests/integration/tls/make_certificates.sh, `forger`). The client reads; the monitor's
// port field and the log's debug line name it, escaped.
TEST_F(OutsideText, ACertificateRoleWithANewlineForgesNoMonitorOrLogLine) {
  const auto monitor = dir.path() / "monitor.log";
  config.monitor_section = "monitor:\n  file: " + monitor.string() + "\n";
  config.log_level = "debug";
  const auto tls_port = free_port();
  config.modbus_extra = tls_section(tls_port, "{ viewer: { write: [] } }");
  start();
  ASSERT_TRUE(wait_for_port(tls_port)) << daemon->log();
  const auto read = tls_client_run(tls_port, "forger", "0400110001");
  ASSERT_EQ(read.status, 0) << read.output << daemon->log();  // served: reads need no role

  // A field of a monitor line is one word: the spaces are escaped there too.
  EXPECT_TRUE(eventually([&] {
    return read_file(monitor).find(" tls:viewer\\nFORGED\\x20line\\x20from\\x20a\\x20certificate@127.0.0.1:") !=
           std::string::npos;
  })) << read_file(monitor);
  EXPECT_EQ(forged_lines(read_file(monitor), monitor_line_start), std::vector<std::string>{}) << read_file(monitor);
  EXPECT_TRUE(daemon->wait_for_log("(role viewer\\nFORGED line from a certificate)")) << daemon->log();
  EXPECT_EQ(forged_lines(daemon->log(), log_line_start), std::vector<std::string>{}) << daemon->log();
}

class OutsideMqttText : public BridgeTest {
 protected:
  void SetUp() override {
    BridgeTest::SetUp();
    broker = std::make_unique<Broker>(dir.path());
    ASSERT_TRUE(broker->start());
    config.extra += site_17_mqtt(*broker, true);
  }
  std::unique_ptr<Broker> broker;
};

// Row 5: "66\n" is a number (the newline is trimmed), so the command is taken and logged;
// the payload stands escaped in its log line. A topic cannot carry a control character
// this far: mosquitto closes the connection of a client that publishes one ("malformed
// packet"), and mosquitto_pub refuses to send it; the topic is escaped in the log all the same.
TEST_F(OutsideMqttText, ACommandPayloadEndingInANewlineForgesNoLogLine) {
  start();
  ASSERT_TRUE(eventually([&] { return broker->subscribe("fleet/site-17/status", 1, 1) == "fleet/site-17/status online\n"; }))
      << daemon->log();
  Subscription results(*broker, dir.path() / "results", "fleet/site-17/set/result");
  publish(*broker, "fleet/site-17/set/W/3", "66\n");
  ASSERT_TRUE(eventually([&] { return payloads(results.lines(), "fleet/site-17/set/result").size() == 1; }))
      << results.lines() << daemon->log();
  EXPECT_EQ(payloads(results.lines(), "fleet/site-17/set/result")[0],
            R"({"topic":"fleet/site-17/set/W/3","ok":true,"error":null})");
  ModbusClient client(config.modbus_port);
  EXPECT_EQ(client.read_holding(0x0103, 1), std::vector<std::uint16_t>{66});
  EXPECT_TRUE(daemon->wait_for_log("mqtt: fleet/site-17/set/W/3 = 66\\n (W)")) << daemon->log();
  EXPECT_EQ(forged_lines(daemon->log(), log_line_start), std::vector<std::string>{}) << daemon->log();
}

using FeedReconnects = BridgeTest;

/// Connects and disconnects `cycles` times, each once the daemon took the connection
/// (its snapshot came); then a client that stays is served at once.
void reconnect(const std::function<Socket()>& connect, int cycles) {
  for (int i = 0; i < cycles; ++i) {
    auto feed = connect();
    ASSERT_TRUE(feed.wait_for_line(R"({"bank":"C","offset":18,"value":0})")) << "cycle " << i;
  }
}

// Row 6: 300 connects and disconnects from one host give its first connect and
// disconnect lines, then counts (once a minute); not 600 lines.
TEST_F(FeedReconnects, ThreeHundredCyclesFromOneHostGiveAHandfulOfLines) {
  start();
  reconnect([&] { return Socket::tcp(config.feed_port); }, 300);
  auto feed = feed_client();
  feed_and_wait(feed, R"({"addr":5,"slot":0,"offset":5,"values":[77]})", 0x0011 + 5, 77);
  EXPECT_LE(daemon->log_count("feed: 127.0.0.1:"), 4u) << daemon->log().substr(0, 4000);
  EXPECT_TRUE(daemon->running());
}

// The same over the unix socket: its clients are told apart by their user (SO_PEERCRED),
// and this test's processes are all one user.
TEST_F(FeedReconnects, ThreeHundredCyclesOfOneUserOnTheUnixSocketGiveAHandfulOfLines) {
  const auto path = (dir.path() / "feed.sock").string();
  config.feed_listen = "unix:" + path;
  start();
  ASSERT_TRUE(eventually([&] { return std::filesystem::exists(path); })) << daemon->log();
  reconnect([&] { return Socket::unix_socket(path); }, 300);
  auto feed = feed_client();
  feed_and_wait(feed, R"({"addr":5,"slot":0,"offset":5,"values":[77]})", 0x0011 + 5, 77);
  EXPECT_LE(daemon->log_count("feed: unix:"), 4u) << daemon->log().substr(0, 4000);
  EXPECT_NE(daemon->log().find("feed: unix:" + path + " uid " + std::to_string(::getuid()) + " connected"),
            std::string::npos)
      << daemon->log().substr(0, 4000);
}

}  // namespace
}  // namespace unima::test
