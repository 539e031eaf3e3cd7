// Configs from afar over MQTT (SPEC §19, issue 40) against the real daemon and a real
// mosquitto: the whole YAML published to <prefix>/config/set with mosquitto_pub, answered
// on <prefix>/config/result or on an MQTT 5 Response Topic with its Correlation Data.
// Applied (the Modbus TCP port moves), refused with the positions of its errors, refused
// when it would turn off the channel it came by, a retained config never applied but
// cleared and counted, and a config that changes the client id answered over the new
// connection.

#include <csignal>
#include <fstream>
#include <future>

#include <nlohmann/json.hpp>

#include "tests/integration/bridge_fixture.hpp"
#include "tests/integration/cli_under_test.hpp"
#include "tests/support/peers/mqtt_broker.hpp"
#include "tests/support/peers/mqtt_subscription.hpp"
#include "tests/support/shell_command.hpp"

namespace unima::test {
namespace {

using namespace std::chrono_literals;
using test_support::Broker;
using test_support::payloads;
using test_support::Subscription;

constexpr auto config_set = "fleet/site-17/config/set";
constexpr auto config_result = "fleet/site-17/config/result";

// Long enough for a new connection and the probe; the waits end as soon as the answer is there.
constexpr auto answer_wait = 20'000ms;

class MqttRemoteConfig : public BridgeTest {
 protected:
  void SetUp() override {
    BridgeTest::SetUp();
    // debug: the broker's log names the client of each PUBLISH it receives.
    broker = std::make_unique<Broker>(dir.path(), "log_type debug\n");
    ASSERT_TRUE(broker->start());
    config.log_level = "info";
    config.extra = taking_configs();
  }

  /// The mqtt section of site 17 with remote_config.mqtt on (a probe of 1 s).
  std::string taking_configs(const std::string& client_id = "site-17", bool remote_mqtt = true) const {
    return "mqtt: { broker: 'mqtt://127.0.0.1:" + std::to_string(broker->port()) + "', client_id: " + client_id +
           ", topic: fleet/site-17, version: " + version + ", publish: { period: 60s } }\n" +
           "remote_config: { mqtt: " + (remote_mqtt ? "true" : "false") + ", probe: 1s }\n";
  }

  /// Started, and subscribed to config/set (the broker says so).
  void start_taking() {
    start();
    ASSERT_TRUE(eventually([&] { return broker->subscriptions_to(config_set) > 0; })) << daemon->log();
  }

  /// The same, the bridge connected with MQTT 5.
  void start_taking_over_mqtt5() {
    version = "5";
    config.extra = taking_configs();
    start_taking();
  }

  /// The running config with the Modbus TCP port moved to a free one.
  BridgeConfig moved() const {
    auto next = config;
    next.modbus_port = free_port();
    return next;
  }

  /// mosquitto_pub of `yaml` (its file kept as `name`) to config/set, QoS 1, with `options`.
  std::filesystem::path send(const std::string& yaml, const std::string& name, const std::string& options = "") const {
    const auto file = dir.path() / name;
    std::ofstream(file) << yaml;
    const auto sent = test_support::run("mosquitto_pub -p " + std::to_string(broker->port()) + " -q 1 -t " + config_set +
                                        " -f " + file.string() + " " + options + " 2>&1");
    EXPECT_EQ(sent.status, 0) << sent.output;
    return file;
  }

  /// The first answer on config/result (subscribed before `action`).
  nlohmann::json answer_after(const std::function<void()>& action) {
    Subscription results(*broker, dir.path() / ("results-" + std::to_string(++subscriptions_)), config_result);
    action();
    std::vector<std::string> answers;
    eventually([&] { return !(answers = payloads(results.lines(), config_result)).empty(); }, answer_wait);
    if (answers.empty()) return nullptr;
    return nlohmann::json::parse(answers.front(), nullptr, false);
  }

  nlohmann::json status_json() const {
    return nlohmann::json::parse(test_support::run(bridge_cli() + " status --json --socket " + config.status_socket).output,
                                 nullptr, false);
  }

  bool serves_on(std::uint16_t port) const {
    ModbusClient client(port);
    return client.read_holding(0x0100, 1).has_value();
  }

  /// Nothing retained on config/set: a new subscriber gets no message there.
  bool nothing_retained() const {
    return broker->subscribe(config_set, 1, 1).find(std::string(config_set) + " ") == std::string::npos;
  }

  std::string version = "3.1.1";
  std::unique_ptr<Broker> broker;
  int subscriptions_ = 0;
};

std::string sha256_of_file(const std::filesystem::path& file) {
  return test_support::run("sha256sum " + file.string()).output.substr(0, 64);
}

TEST_F(MqttRemoteConfig, AConfigOnConfigSetIsAppliedAndAnsweredOnConfigResult) {
  start_taking();
  const auto moved = free_port();
  auto next = config;
  next.modbus_port = moved;
  std::filesystem::path file;
  const auto answer = answer_after([&] { file = send(next.yaml(), "moved.yaml"); });
  ASSERT_TRUE(answer.is_object()) << daemon->log();
  EXPECT_EQ(answer["result"], "applied") << answer.dump() << daemon->log();
  EXPECT_EQ(answer["id"], sha256_of_file(file)) << answer.dump();
  EXPECT_EQ(answer["source"], "mqtt");
  EXPECT_EQ(answer["by"], "mqtt") << "no user property `by`: the channel's name";
  EXPECT_TRUE(serves_on(moved));
  EXPECT_FALSE(serves_on(config.modbus_port));
  const auto status = status_json();
  EXPECT_EQ(status["config_in_force"]["source"], "mqtt") << status.dump();
  EXPECT_EQ(status["config_in_force"]["sha256"], sha256_of_file(file)) << status.dump();
  EXPECT_TRUE(daemon->wait_for_log("remote config: mqtt by mqtt: applied")) << daemon->log();
}

TEST_F(MqttRemoteConfig, AConfigWithErrorsIsRefusedWithTheirLineAndColumn) {
  start_taking();
  auto broken = config;
  broken.modbus_port = free_port();
  broken.extra += "no_such_section: 1\n";
  const auto yaml = broken.yaml();
  const auto line = std::count(yaml.begin(), yaml.begin() + static_cast<long>(yaml.find("no_such_section")), '\n') + 1;
  const auto answer = answer_after([&] { send(yaml, "broken.yaml"); });
  ASSERT_TRUE(answer.is_object()) << daemon->log();
  EXPECT_EQ(answer["result"], "refused") << answer.dump();
  ASSERT_FALSE(answer["errors"].empty()) << answer.dump();
  EXPECT_EQ(answer["errors"][0]["line"], line) << answer.dump();
  EXPECT_EQ(answer["errors"][0]["column"], 1) << answer.dump();
  EXPECT_TRUE(serves_on(config.modbus_port));
  EXPECT_FALSE(serves_on(broken.modbus_port));
}

// The retained birth names the config in force and how the last change ended, so a
// fleet's inventory learns both without asking each bridge — a refused change too.
TEST_F(MqttRemoteConfig, TheRetainedBirthNamesTheConfigInForceAndTheLastChange) {
  constexpr auto birth_topic = "fleet/site-17/birth";
  const auto retained_birth = [&] {
    const auto text = broker->subscribe(birth_topic, 1);
    const auto at = text.find('{');
    return at == std::string::npos ? nlohmann::json() : nlohmann::json::parse(text.substr(at), nullptr, false);
  };
  start_taking();
  ASSERT_TRUE(eventually([&] { return retained_birth().is_object(); })) << daemon->log();
  auto birth = retained_birth();
  EXPECT_EQ(birth["config"]["source"], "file") << birth.dump();
  EXPECT_TRUE(birth["config"]["last_result"].is_null()) << birth.dump();

  const auto next = moved();
  std::filesystem::path file;
  ASSERT_EQ(answer_after([&] { file = send(next.yaml(), "moved.yaml"); })["result"], "applied") << daemon->log();
  EXPECT_TRUE(eventually([&] { return retained_birth()["config"]["last_result"] == "applied"; })) << retained_birth().dump();
  birth = retained_birth();
  EXPECT_EQ(birth["config_sha256"], sha256_of_file(file)) << birth.dump();
  EXPECT_EQ(birth["config"]["source"], "mqtt") << birth.dump();
  EXPECT_EQ(birth["config"]["by"], "mqtt") << birth.dump();
  EXPECT_EQ(birth["config"]["number"], 1) << birth.dump();
  EXPECT_TRUE(birth["config"]["applied_at"].is_string()) << birth.dump();

  auto broken = next;
  broken.extra += "no_such_section: 1\n";
  ASSERT_EQ(answer_after([&] { send(broken.yaml(), "broken.yaml"); })["result"], "refused") << daemon->log();
  EXPECT_TRUE(eventually([&] { return retained_birth()["config"]["last_result"] == "refused"; })) << retained_birth().dump();
  birth = retained_birth();
  EXPECT_EQ(birth["config"]["source"], "mqtt") << "a refused change leaves the config in force: " << birth.dump();
  EXPECT_EQ(birth["config_sha256"], sha256_of_file(file)) << birth.dump();
  EXPECT_TRUE(birth["config"]["last_reason"].is_string()) << birth.dump();
}

// A config that turns remote_config.mqtt off would leave the fleet no way back to this bridge.
TEST_F(MqttRemoteConfig, AConfigThatTurnsOffItsOwnChannelIsRefused) {
  start_taking();
  auto locking = config;
  locking.modbus_port = free_port();
  locking.extra = taking_configs("site-17", false);
  const auto answer = answer_after([&] { send(locking.yaml(), "locking.yaml"); });
  ASSERT_TRUE(answer.is_object()) << daemon->log();
  EXPECT_EQ(answer["result"], "refused") << answer.dump();
  EXPECT_NE(answer["reason"].get<std::string>().find("remote_config.mqtt"), std::string::npos) << answer.dump();
  EXPECT_TRUE(serves_on(config.modbus_port));
  EXPECT_EQ(status_json()["config_in_force"]["source"], "file");
}

// Retained before the bridge came: it reaches the bridge from the broker's store, flagged.
TEST_F(MqttRemoteConfig, ARetainedConfigIsNotAppliedButClearedAndCounted) {
  const auto next = moved();
  send(next.yaml(), "retained.yaml", "-r");
  start();
  ASSERT_TRUE(eventually([&] { return status_json()["mqtt"]["retained_configs_dropped"] == 1; })) << daemon->log();
  EXPECT_TRUE(daemon->wait_for_log("retained config on fleet/site-17/config/set")) << daemon->log();
  EXPECT_TRUE(eventually([&] { return nothing_retained(); }, 10'000ms));
  EXPECT_TRUE(serves_on(config.modbus_port));
  EXPECT_FALSE(serves_on(next.modbus_port));
  EXPECT_EQ(status_json()["config_in_force"]["source"], "file");
}

// With MQTT 5 the bridge asks for Retain As Published: a retained config published while it
// is connected is seen as retained too (MQTT 3.1.1 brokers clear the flag on the way).
TEST_F(MqttRemoteConfig, WithMqtt5ARetainedConfigPublishedWhileConnectedIsNotAppliedButCleared) {
  start_taking_over_mqtt5();
  const auto next = moved();
  send(next.yaml(), "retained.yaml", "-V 5 -r");
  ASSERT_TRUE(eventually([&] { return status_json()["mqtt"]["retained_configs_dropped"] == 1; })) << daemon->log();
  EXPECT_TRUE(eventually([&] { return nothing_retained(); }, 10'000ms));
  EXPECT_TRUE(serves_on(config.modbus_port));
  EXPECT_FALSE(serves_on(next.modbus_port));
}

// The fleet's application as paho-mqtt makes it (MQTT 5, tests/integration/mqtt/
// mqtt5_request.py): the answer comes on its Response Topic, with its Correlation Data.
TEST_F(MqttRemoteConfig, APahoClientsConfigIsAnsweredOnItsResponseTopicWithItsCorrelationData) {
  start_taking_over_mqtt5();
  const auto next = moved();
  const auto file = dir.path() / "paho.yaml";
  std::ofstream(file) << next.yaml();
  const auto asked = test_support::run(std::string(UNIMA_SOURCE_DIR) + "/tests/integration/mqtt/mqtt5_request.py " +
                                       std::to_string(broker->port()) + " " + config_set + " @" + file.string() +
                                       " fleet/site-17/reply/paho 5eed01 2>&1");
  const std::string head = "answer: ";
  ASSERT_TRUE(asked.output.starts_with(head)) << asked.output << daemon->log();
  const auto end = asked.output.find('\n');
  const auto answer = nlohmann::json::parse(asked.output.substr(head.size(), end - head.size()), nullptr, false);
  EXPECT_EQ(answer["result"], "applied") << asked.output;
  EXPECT_EQ(answer["id"], sha256_of_file(file)) << asked.output;
  EXPECT_NE(asked.output.find("\ncorrelation: 5eed01\n"), std::string::npos) << asked.output;
  EXPECT_TRUE(serves_on(next.modbus_port));
}

TEST_F(MqttRemoteConfig, AnMqtt5ConfigIsAnsweredOnItsResponseTopicWithItsCorrelationDataAndAuthor) {
  start_taking_over_mqtt5();
  const std::string reply = "fleet/site-17/reply/ops/42";
  const auto subscribed = broker->subscriptions_to(reply);
  auto on_reply = std::async(std::launch::async, [&] {
    return test_support::run("mosquitto_sub -V 5 -p " + std::to_string(broker->port()) + " -t " + reply +
                             " -F '%t|%D|%p' -C 1 -W 20 2>&1")
        .output;
  });
  ASSERT_TRUE(eventually([&] { return broker->subscriptions_to(reply) > subscribed; }));
  Subscription results(*broker, dir.path() / "results", config_result);
  const auto next = moved();
  send(next.yaml(), "moved.yaml",
       "-V 5 -D publish response-topic " + reply + " -D publish correlation-data c0ffee01 -D publish user-property by alice");
  const auto line = on_reply.get();
  const auto head = reply + "|c0ffee01|";
  ASSERT_TRUE(line.starts_with(head)) << line << daemon->log();
  const auto answer = nlohmann::json::parse(line.substr(head.size()), nullptr, false);
  EXPECT_EQ(answer["result"], "applied") << line;
  EXPECT_EQ(answer["by"], "alice") << line;
  EXPECT_TRUE(serves_on(next.modbus_port));
  EXPECT_TRUE(payloads(results.lines(), config_result).empty()) << "answered once, where asked: " << results.lines();
}

// The config changes the client id: the bridge leaves the broker and comes back as another
// client, and the answer goes out over that new connection.
TEST_F(MqttRemoteConfig, AConfigThatChangesTheClientIdIsAnsweredOverTheNewConnection) {
  start_taking();
  auto next = config;
  next.extra = taking_configs("site-17-new");
  const auto answer = answer_after([&] { send(next.yaml(), "new-client.yaml"); });
  ASSERT_TRUE(answer.is_object()) << daemon->log();
  EXPECT_EQ(answer["result"], "applied") << answer.dump() << daemon->log();
  EXPECT_EQ(status_json()["mqtt"]["client_id"], "site-17-new");
  const auto log = test_support::read_file(dir.path() / "mosquitto.log");
  EXPECT_NE(log.find("Received PUBLISH from site-17-new (d0, q1, r0, m"), std::string::npos);
  bool over_new = false;
  for (auto at = log.find("Received PUBLISH from "); at != std::string::npos; at = log.find("Received PUBLISH from ", at + 1)) {
    const auto end = log.find('\n', at);
    const auto entry = log.substr(at, end - at);
    if (entry.find(config_result) == std::string::npos) continue;
    EXPECT_TRUE(entry.starts_with("Received PUBLISH from site-17-new ")) << entry;
    over_new = true;
  }
  EXPECT_TRUE(over_new) << log;
}

// The broker the config names never answers: the previous config, and its connection, come
// back, and the answer waits for that connection (the flow ends before it is up again).
TEST_F(MqttRemoteConfig, AConfigWhoseBrokerNeverAnswersIsRolledBackAndAnsweredOnceTheOldConnectionIsBack) {
  start_taking();
  auto unreachable = config;
  unreachable.modbus_port = free_port();
  unreachable.extra = "mqtt: { broker: 'mqtt://127.0.0.1:" + std::to_string(free_port()) +
                      "', client_id: site-17, topic: fleet/site-17 }\nremote_config: { mqtt: true, probe: 1s }\n";
  const auto answer = answer_after([&] { send(unreachable.yaml(), "unreachable.yaml"); });
  ASSERT_TRUE(answer.is_object()) << daemon->log();
  EXPECT_EQ(answer["result"], "rolled_back") << answer.dump() << daemon->log();
  EXPECT_NE(answer["reason"].get<std::string>().find("MQTT broker"), std::string::npos) << answer.dump();
  EXPECT_TRUE(serves_on(config.modbus_port));
  EXPECT_EQ(status_json()["config_in_force"]["source"], "file");
}

// remote_config.mqtt turned on by a reload that keeps the client: the bridge subscribes
// config/set on the connection it has.
TEST_F(MqttRemoteConfig, AReloadThatTurnsRemoteConfigMqttOnSubscribesWithoutANewConnection) {
  config.extra = taking_configs("site-17", false);
  start();
  ASSERT_TRUE(eventually([&] { return status_json()["mqtt"]["connected"] == true; })) << daemon->log();
  EXPECT_EQ(broker->subscriptions_to(config_set), 0u);
  config.extra = taking_configs();
  daemon->rewrite_config(config.yaml());
  daemon->signal(SIGHUP);
  ASSERT_TRUE(eventually([&] { return broker->subscriptions_to(config_set) > 0; })) << daemon->log();
  EXPECT_EQ(status_json()["mqtt"]["connections"], 1) << "the same connection";
  const auto next = moved();
  const auto answer = answer_after([&] { send(next.yaml(), "moved.yaml"); });
  ASSERT_TRUE(answer.is_object()) << daemon->log();
  EXPECT_EQ(answer["result"], "applied") << answer.dump() << daemon->log();
  EXPECT_TRUE(serves_on(next.modbus_port));
}

}  // namespace
}  // namespace unima::test
