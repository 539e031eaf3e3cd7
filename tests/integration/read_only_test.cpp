// modbus.tcp.read_only is the site's freeze switch (SPEC §11; issue 29 row 8): while it is
// on, no way in writes — not the plain port, not the TLS port whatever the role, not the
// RTU port, not an MQTT command — and a reload that turns it on stops them all without touching their
// sections. An MQTT command is answered ok: false with the reason, and the log warns
// once, at start and on reload, that commands will be refused.

#include <csignal>

#include "tests/integration/certificate_fixture.hpp"
#include "tests/integration/rtu_fixture.hpp"
#include "tests/support/peers/mqtt_broker.hpp"
#include "tests/support/peers/mqtt_subscription.hpp"

namespace unima::test {
namespace {

using test_support::Broker;
using test_support::payloads;
using test_support::publish;
using test_support::Subscription;

const std::string warning = "mqtt.commands is true, but modbus.tcp.read_only is on";
const std::string refused = R"("ok":false,"error":"read only: modbus.tcp.read_only is on, no command is taken"})";

class ReadOnly : public CertificateTest {
 protected:
  void SetUp() override {
    CertificateTest::SetUp();
    broker = std::make_unique<Broker>(dir.path());
    ASSERT_TRUE(broker->start());
    config.extra += site_17_mqtt(*broker, true);
    config.extra += "state: { file: " + (dir.path() / "state").string() + " }\n";
  }
  void start_online() {
    start();
    ASSERT_TRUE(eventually([&] { return broker->subscribe("fleet/site-17/status", 1, 1) == "fleet/site-17/status online\n"; }))
        << daemon->log();
  }
  /// Publishes a command and returns its answer on set/result.
  std::string command(const std::string& topic, const std::string& payload) {
    Subscription results(*broker, dir.path() / ("results-" + std::to_string(++commands_)), "fleet/site-17/set/result");
    publish(*broker, "fleet/site-17/set/" + topic, payload);
    std::vector<std::string> answers;
    eventually([&] { return !(answers = payloads(results.lines(), "fleet/site-17/set/result")).empty(); });
    return answers.empty() ? std::string("no answer") : answers.front();
  }
  std::optional<std::vector<std::uint16_t>> w(int offset) {
    ModbusClient client(config.modbus_port);
    return client.read_holding(0x0100 + offset, 1);
  }

  std::unique_ptr<Broker> broker;
  int commands_ = 0;
};

TEST_F(ReadOnly, AnMqttCommandIsRefusedWithTheReasonAndChangesNothing) {
  config.tcp_extra = ", read_only: true";
  start_online();
  EXPECT_EQ(daemon->log_count(warning), 1u) << daemon->log();
  EXPECT_EQ(command("W/3", "1234"), R"({"topic":"fleet/site-17/set/W/3",)" + refused);
  EXPECT_EQ(command("X/2", "1"), R"({"topic":"fleet/site-17/set/X/2",)" + refused);
  EXPECT_EQ(w(3), std::vector<std::uint16_t>{0x7FFF});  // never written
  ModbusClient plain(config.modbus_port);
  EXPECT_FALSE(plain.write(0x0103, 7));  // and the plain port, as ever
  EXPECT_EQ(w(3), std::vector<std::uint16_t>{0x7FFF});
}

TEST_F(ReadOnly, AReloadThatTurnsItOnStopsMqttCommandsAndOneThatTurnsItOffLetsThemIn) {
  start_online();
  EXPECT_EQ(command("W/3", "1234"), R"({"topic":"fleet/site-17/set/W/3","ok":true,"error":null})");
  EXPECT_EQ(daemon->log_count(warning), 0u) << daemon->log();

  config.tcp_extra = ", read_only: true";
  daemon->rewrite_config(config.yaml());
  daemon->signal(SIGHUP);
  ASSERT_TRUE(daemon->wait_for_log("bridge: reloaded")) << daemon->log();
  EXPECT_EQ(daemon->log_count(warning), 1u) << daemon->log();
  EXPECT_EQ(command("W/3", "99"), R"({"topic":"fleet/site-17/set/W/3",)" + refused);
  EXPECT_EQ(w(3), std::vector<std::uint16_t>{1234});

  config.tcp_extra = "";
  daemon->rewrite_config(config.yaml());
  daemon->signal(SIGHUP);
  ASSERT_TRUE(eventually([&] { return daemon->log_count("bridge: reloaded") == 2; })) << daemon->log();
  EXPECT_EQ(command("W/3", "99"), R"({"topic":"fleet/site-17/set/W/3","ok":true,"error":null})");
  EXPECT_EQ(w(3), std::vector<std::uint16_t>{99});
}

// The TLS port's operator may write W, but not while the bridge is read-only.
TEST_F(ReadOnly, TheTlsPortRefusesEvenARoleThatMayWrite) {
  config.tcp_extra = ", read_only: true";
  const auto tls_port = free_port();
  config.modbus_extra = tls_section(tls_port, "{ operator: { write: [W, X] } }");
  start_online();
  ASSERT_TRUE(wait_for_port(tls_port)) << daemon->log();
  const auto written = tls_client_run(tls_port, "operator", "0601030007 0401030001");
  EXPECT_NE(written.output.find("\n8601\n"), std::string::npos) << written.output << daemon->log();  // exception 01
  EXPECT_NE(written.output.find("\n0402" "7fff\n"), std::string::npos) << written.output;  // W+3 unchanged
  EXPECT_EQ(w(3), std::vector<std::uint16_t>{0x7FFF});
}

using ReadOnlyRtu = RtuTest;

TEST_F(ReadOnlyRtu, TheRtuPortAnswersAWriteWithIllegalFunction) {
  config.tcp_extra = ", read_only: true";
  start_rtu();
  EXPECT_EQ(exchange(rtu_adu(1, {0x06, 0x01, 0x03, 0x01, 0x00}), 5), rtu_adu(1, {0x86, 0x01}));
  EXPECT_EQ(exchange(rtu_adu(1, {0x10, 0x01, 0x03, 0x00, 0x01, 0x02, 0x01, 0x00}), 5), rtu_adu(1, {0x90, 0x01}));
  ModbusClient tcp(config.modbus_port);
  EXPECT_EQ(tcp.read_input(0x0103, 1), std::vector<std::uint16_t>{0x7FFF});
}

}  // namespace
}  // namespace unima::test
