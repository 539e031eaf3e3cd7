// MQTT for fleets (SPEC §15, issue 32) against a real mosquitto: the birth before any bank
// document, two bridges given one client id that do not flap, and MQTT 5 commands answered
// where the client asks, with paho-mqtt as the fleet's application
// (tests/integration/mqtt/mqtt5_request.py).

#include <unistd.h>

#include <csignal>
#include <fstream>
#include <thread>

#include <nlohmann/json.hpp>

#include "tests/integration/bridge_fixture.hpp"
#include "tests/support/peers/mqtt_broker.hpp"
#include "tests/support/peers/mqtt_subscription.hpp"

namespace unima::test {
namespace {

using namespace std::chrono_literals;
using test_support::Broker;
using test_support::payloads;
using test_support::Subscription;

class MqttFleet : public BridgeTest {
 protected:
  void SetUp() override {
    BridgeTest::SetUp();
    broker = std::make_unique<Broker>(dir.path());
    ASSERT_TRUE(broker->start());
  }
  /// The mqtt section for this broker: `client_id` under fleet/<client_id>, and `more` keys.
  std::string mqtt_section(const std::string& client_id, const std::string& more = "") const {
    return "mqtt: { broker: 'mqtt://127.0.0.1:" + std::to_string(broker->port()) + "', client_id: " + client_id +
           ", topic: fleet/" + client_id + ", publish: { period: 60s }" + more + " }\n";
  }
  /// Started with MQTT 5 commands (and `more` keys), once it is online: the command line
  /// of tests/integration/mqtt/mqtt5_request.py for this broker.
  std::string start_with_mqtt5_commands(const std::string& more = "") {
    config.extra = mqtt_section("site-17", ", version: 5, commands: true" + more);
    start();
    EXPECT_TRUE(eventually([&] { return broker->subscribe("fleet/site-17/status", 1, 1) == "fleet/site-17/status online\n"; }))
        << daemon->log();
    return std::string(UNIMA_SOURCE_DIR) + "/tests/integration/mqtt/mqtt5_request.py " + std::to_string(broker->port());
  }
  std::unique_ptr<Broker> broker;
};

/// The "topic payload" lines of `lines` whose topic starts with `prefix`, in their order.
std::vector<std::string> lines_under(const std::string& lines, const std::string& prefix) {
  std::vector<std::string> found;
  std::size_t at = 0;
  while (at < lines.size()) {
    const auto end = lines.find('\n', at);
    const auto line = lines.substr(at, end == std::string::npos ? std::string::npos : end - at);
    if (line.starts_with(prefix)) found.push_back(line);
    if (end == std::string::npos) break;
    at = end + 1;
  }
  return found;
}

std::string this_host_name() {
  char name[256] = {};
  ::gethostname(name, sizeof name - 1);
  return name;
}

// Subscribed to everything before the bridge starts: the first message under its prefix
// is the birth — before `online`, before any bank — with the fields of SPEC §15, and its
// config_sha256 is what sha256sum says of the config file.
TEST_F(MqttFleet, TheBirthComesFirstAndNamesVersionConfigAndMachine) {
  config.extra = mqtt_section("site-17");
  Subscription everything(*broker, dir.path() / "all", "#");
  start();
  ASSERT_TRUE(eventually([&] { return !payloads(everything.lines(), "fleet/site-17/D1").empty(); }, 8000ms)) << daemon->log();
  const auto lines = lines_under(everything.lines(), "fleet/site-17/");
  ASSERT_GE(lines.size(), 3u) << everything.lines();
  ASSERT_TRUE(lines[0].starts_with("fleet/site-17/birth ")) << everything.lines();
  EXPECT_EQ(lines[1], "fleet/site-17/status online") << everything.lines();

  const auto birth = nlohmann::json::parse(lines[0].substr(std::string("fleet/site-17/birth ").size()));
  EXPECT_TRUE(birth["version"].is_string() && !birth["version"].get<std::string>().empty()) << birth.dump();
  const auto sum = run("sha256sum " + daemon->config_path().string()).output;
  EXPECT_EQ(birth["config_sha256"], sum.substr(0, 64)) << birth.dump();
  ASSERT_TRUE(birth["started"].is_string()) << birth.dump();
  EXPECT_TRUE(birth["started"].get<std::string>().ends_with("Z")) << birth.dump();
  EXPECT_EQ(birth["hostname"], this_host_name()) << birth.dump();
  std::ifstream machine_id("/etc/machine-id");
  std::string id;
  if (machine_id && std::getline(machine_id, id) && id.size() == 32) EXPECT_EQ(birth["machine_id"], id.substr(0, 8)) << birth.dump();
  else EXPECT_TRUE(birth["machine_id"].is_null()) << birth.dump();
  EXPECT_TRUE(birth["clock_synced"].is_boolean()) << birth.dump();

  // Retained: a subscriber that comes later gets it.
  EXPECT_TRUE(broker->subscribe("fleet/site-17/birth", 1, 2).starts_with("fleet/site-17/birth {\"version\""));

  // A reload that keeps the client but changes the file: a new birth names the new file.
  Subscription births(*broker, dir.path() / "births", "fleet/site-17/birth");
  daemon->rewrite_config(read_file(daemon->config_path()) + "# edited\n");
  daemon->signal(SIGHUP);
  const auto edited = run("sha256sum " + daemon->config_path().string()).output.substr(0, 64);
  EXPECT_TRUE(eventually([&] {
    const auto all = payloads(births.lines(), "fleet/site-17/birth");
    return !all.empty() && nlohmann::json::parse(all.back())["config_sha256"] == edited;
  })) << births.lines() << daemon->log();
}

// Two bridges given one client id (a copied config): the broker gives the session to
// whichever connected last. Each bridge, once it sees that, logs an error naming the id and
// waits 30 s, so over a minute each connects a few times, not the thirty or more a flap
// with a 1 s back-off would make. MQTT 5 and 3.1.1 side by side, on one broker, in one
// minute. The minute is the issue's measure: the back-off is the real 30 s, so a shorter
// window would see only the first hold. Debian 12's mosquitto (2.0.11) does not send MQTT
// 5's DISCONNECT 0x8E "session taken over" (mosquitto sends it from 2.0.15 on): it closes
// the connection for both protocols, so both pairs meet the rule for a broker that just
// closes (young connections closed twice in a row, mqtt/session_takeover); the reason
// code's path is the unit test's (Takeover.Mqtt5SaysSoAtOnce).
TEST_F(MqttFleet, TwoBridgesWithOneClientIdDoNotFlap) {
  struct Twin {
    TempDir dir;
    BridgeConfig config;
    std::unique_ptr<Daemon> daemon;
  };
  std::vector<std::unique_ptr<Twin>> twins;
  for (const auto& [id, version] : {std::pair{"twin-5", "5"}, std::pair{"twin-5", "5"}, std::pair{"twin-311", "3.1.1"},
                                    std::pair{"twin-311", "3.1.1"}}) {
    auto twin = std::make_unique<Twin>();
    twin->config.modbus_port = free_port();
    twin->config.feed_port = free_port();
    twin->config.status_socket = (twin->dir.path() / "control.sock").string();
    twin->config.log_level = "info";
    twin->config.extra = mqtt_section(id, std::string(", version: '") + version + "'");
    twins.push_back(std::move(twin));
  }
  const auto connects = [](const Twin& twin) { return twin.daemon->log_count("mqtt: connected to"); };
  // The first of each pair, connected; then the second.
  for (const std::size_t first : {0u, 2u}) {
    twins[first]->daemon = std::make_unique<Daemon>(twins[first]->dir, twins[first]->config.yaml());
    ASSERT_TRUE(eventually([&] { return connects(*twins[first]) == 1; }, 8000ms)) << twins[first]->daemon->log();
  }
  for (const std::size_t second : {1u, 3u})
    twins[second]->daemon = std::make_unique<Daemon>(twins[second]->dir, twins[second]->config.yaml());

  // The minute, watched each second so that a flap fails at once.
  const auto until = std::chrono::steady_clock::now() + 60s;
  while (std::chrono::steady_clock::now() < until) {
    for (const auto& twin : twins) ASSERT_LE(connects(*twin), 3u) << twin->daemon->log();
    std::this_thread::sleep_for(1s);
  }
  for (const auto& twin : twins) EXPECT_LE(connects(*twin), 3u) << twin->daemon->log();

  // In each pair a bridge saw the takeover, said so naming the id, and its status counts
  // it and says when; a bridge that saw none says null.
  for (const auto& [first, id] : {std::pair{0u, "twin-5"}, std::pair{2u, "twin-311"}}) {
    const auto said = "gave the session of client id " + std::string(id) + " to another client";
    bool seen = false;
    for (const auto* twin : {twins[first].get(), twins[first + 1].get()}) {
      const auto status = run(std::string(UNIMA_BRIDGE_CLI) + " status --json --socket " + twin->config.status_socket);
      ASSERT_EQ(status.status, 0) << status.output;
      const auto mqtt = nlohmann::json::parse(status.output)["mqtt"];
      const auto taken = twin->daemon->log_count(said);
      EXPECT_EQ(mqtt["session_takeovers"], taken) << mqtt.dump() << twin->daemon->log();
      if (taken == 0) {
        EXPECT_TRUE(mqtt["last_takeover"].is_null()) << mqtt.dump();
        continue;
      }
      seen = true;
      EXPECT_TRUE(mqtt["last_takeover"].is_string() && mqtt["last_takeover"].get<std::string>().ends_with("Z")) << mqtt.dump();
      const auto text = run(std::string(UNIMA_BRIDGE_CLI) + " status --socket " + twin->config.status_socket).output;
      EXPECT_NE(text.find("session taken over by another client with this id"), std::string::npos) << text;
    }
    EXPECT_TRUE(seen) << twins[first]->daemon->log() << twins[first + 1]->daemon->log();
  }
}

// MQTT 5's request/response: a command with Response Topic and Correlation Data is
// answered on that topic (under <prefix>/reply/, the default mqtt.response_topics) with
// the same correlation data; the write is a Modbus write. One without them is answered on
// set/result as before.
TEST_F(MqttFleet, AnMqtt5CommandIsAnsweredWhereItAsksWithItsCorrelationData) {
  const auto request = start_with_mqtt5_commands();
  ASSERT_FALSE(HasFailure());
  const auto asked = run(request + " fleet/site-17/set/W/3 1234 fleet/site-17/reply/17 c0ffee0117 2>&1");
  EXPECT_EQ(asked.output,
            "answer: {\"topic\":\"fleet/site-17/set/W/3\",\"ok\":true,\"error\":null}\ncorrelation: c0ffee0117\n");
  ModbusClient client(config.modbus_port);
  EXPECT_EQ(client.read_holding(0x0103, 1), std::vector<std::uint16_t>{1234});

  const auto refused = run(request + " fleet/site-17/set/W/16 1 fleet/site-17/reply/17 0a0b 2>&1");
  EXPECT_EQ(refused.output,
            "answer: {\"topic\":\"fleet/site-17/set/W/16\",\"ok\":false,\"error\":\"W has the offsets 0..15, not '16'\"}\n"
            "correlation: 0a0b\n");

  const auto plain = run(request + " fleet/site-17/set/X/2 1 fleet/site-17/set/result 00 --no-properties 2>&1");
  EXPECT_EQ(plain.output, "answer: {\"topic\":\"fleet/site-17/set/X/2\",\"ok\":true,\"error\":null}\ncorrelation: none\n");
}

// Issue 43, finding 2: whoever may publish set/… chose where the bridge published, with
// its own credentials. A Response Topic that is one of the bridge's own topics, or not in
// mqtt.response_topics, is not answered on: the answer goes to set/result, nothing with
// the correlation data goes where it asked, and the refusal is counted and logged once.
TEST_F(MqttFleet, AnMqtt5CommandIsNeverAnsweredOnTheBridgesOwnTopicsOrOutsideTheList) {
  const auto request = start_with_mqtt5_commands(", response_topics: ['fleet/site-17/reply/#', 'apps/#']");
  ASSERT_FALSE(HasFailure());
  const auto result_topic = std::string(" --answer-on fleet/site-17/set/result");
  const std::vector<std::string> refused{"fleet/site-17/status", "fleet/site-17/set/W/4", "spBv1.0/plant-7/NCMD/bridge-17",
                                         "fleet/site-18/set/W/3"};
  for (const auto& where : refused) {
    const auto asked = run(request + " fleet/site-17/set/W/3 77 " + where + " c0ffee" + result_topic + " 2>&1");
    EXPECT_EQ(asked.output, "answer: {\"topic\":\"fleet/site-17/set/W/3\",\"ok\":true,\"error\":null}\n"
                            "correlation: none\non " + where + ": 0 with the correlation data\n")
        << where << daemon->log();
  }
  // The write itself was taken; only where its answer went was refused.
  ModbusClient client(config.modbus_port);
  EXPECT_EQ(client.read_holding(0x0103, 1), std::vector<std::uint16_t>{77});

  // Where the list allows it, the answer goes there.
  for (const auto* where : {"fleet/site-17/reply/x", "apps/scada/replies"}) {
    const auto asked = run(request + " fleet/site-17/set/W/5 9 " + where + " 0102 2>&1");
    EXPECT_EQ(asked.output, "answer: {\"topic\":\"fleet/site-17/set/W/5\",\"ok\":true,\"error\":null}\ncorrelation: 0102\n")
        << where << daemon->log();
  }

  const auto status = run(std::string(UNIMA_BRIDGE_CLI) + " status --json --socket " + config.status_socket);
  ASSERT_EQ(status.status, 0) << status.output;
  EXPECT_EQ(nlohmann::json::parse(status.output)["mqtt"]["response_topics_refused"], refused.size()) << status.output;
  EXPECT_EQ(daemon->log_count("mqtt: the Response Topic fleet/site-17/status of a command on fleet/site-17/set/W/3 is "
                              "one of the bridge's own topics: answered on fleet/site-17/set/result instead"),
            1u)
      << daemon->log();
  EXPECT_EQ(daemon->log_count("mqtt: the Response Topic "), 1u) << daemon->log();  // the rest counted, not logged
}

}  // namespace
}  // namespace unima::test
