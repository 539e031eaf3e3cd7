// Home Assistant's MQTT discovery (SPEC §15) against a real broker: Debian's `mosquitto`,
// and its `mosquitto_sub` / `mosquitto_pub` in Home Assistant's place — the retained
// configs, checked against the discovery schema's rules (unique ids, state topics the
// bridge publishes, templates that reach the value in the real document, availability,
// devices) and Home Assistant's documented classes, units and categories (tests/data), W/X entities only with commands and their commands taking effect, the configs
// again when Home Assistant says `online`, and the entities of a D_N a reload drops removed.

#include <cmath>
#include <csignal>
#include <map>
#include <set>
#include <sstream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "tests/integration/bridge_fixture.hpp"
#include "tests/support/home_assistant_schema.hpp"
#include "tests/support/home_assistant_template.hpp"
#include "tests/support/peers/mqtt_broker.hpp"
#include "tests/support/peers/mqtt_subscription.hpp"

namespace unima::test {
namespace {

using namespace std::chrono_literals;
using Json = nlohmann::ordered_json;
using test_support::Broker;
using test_support::jinja_text;
using test_support::payloads;
using test_support::publish;
using test_support::Subscription;
using test_support::template_value;

/// The messages retained under `pattern` now, by topic: what a client that subscribes
/// now (Home Assistant starting) gets. mosquitto_sub takes them for a second (-W 1).
std::map<std::string, std::string> retained(const Broker& broker, const std::string& pattern) {
  const auto output = run("mosquitto_sub -p " + std::to_string(broker.port()) + " -t '" + pattern +
                          "' -v --retained-only -W 1 2>/dev/null").output;
  std::map<std::string, std::string> messages;
  std::istringstream lines(output);
  for (std::string line; std::getline(lines, line);) {
    if (line == "Timed out") continue;  // mosquitto_sub's word on -W, on its standard output
    const auto space = line.find(' ');
    if (space != std::string::npos) messages[line.substr(0, space)] = line.substr(space + 1);
  }
  return messages;
}

/// What Home Assistant sends for a number entity set to `value`: its `command_template`
/// rendered by Jinja (Debian's python3-jinja2), with `value` an integer when it is whole,
/// as Home Assistant's MQTT number passes it.
std::string home_assistant_renders(const std::string& command_template, double value) {
  const auto number = value == std::floor(value) ? std::to_string(static_cast<long>(value)) : fmt::format("{}", value);
  const auto script = "import jinja2, sys; print(jinja2.Environment().from_string(sys.argv[1]).render(value=" + number + "), end='')";
  const auto rendered = run("python3 -c \"" + script + "\" '" + command_template + "'");
  EXPECT_EQ(rendered.status, 0) << rendered.output;
  return rendered.output;
}

std::string with_key(std::string section, const std::string& key) {
  return section.replace(section.find("publish:"), 0, key + ", ");
}

class MqttDiscovery : public BridgeTest {
 protected:
  void SetUp() override {
    BridgeTest::SetUp();
    broker = std::make_unique<Broker>(dir.path());
    ASSERT_TRUE(broker->start());
    config.banks = "{ D1: 0x0011, D2: 0x0200, W: 0x0100 }";
    config.devices = "{ D1: { type: unigen-chp, address: 5 }, D2: { type: uis, address: 6 } }\n"
                     "mapping: { A: [ D1.oil_temperature ], B: [ D1+0x11.7 ] }";
    config.extra = with_key(test_support::site_17_mqtt(*broker), "discovery: {}");
  }
  /// The configs, once the bridge has published them: a document is retained, and the
  /// configs go before the documents on the connection.
  std::map<std::string, Json> configs() {
    EXPECT_TRUE(eventually([&] { return !broker->subscribe("fleet/site-17/D1", 1, 1).empty(); }, 8000ms)) << daemon->log();
    std::map<std::string, Json> parsed;
    for (const auto& [topic, payload] : retained(*broker, "homeassistant/#"))
      if (topic != "homeassistant/status") parsed[topic] = Json::parse(payload);
    return parsed;
  }
  static std::size_t count_component(const std::map<std::string, Json>& configs, const std::string& component) {
    std::size_t count = 0;
    for (const auto& [topic, payload] : configs) count += topic.starts_with("homeassistant/" + component + "/");
    return count;
  }
  std::unique_ptr<Broker> broker;
};

// What Home Assistant finds on the broker, checked as its discovery schema asks.
TEST_F(MqttDiscovery, RetainedConfigsFollowHomeAssistantsSchemaAndReachThePublishedValues) {
  start();
  auto feed = feed_client();
  feed_and_wait(feed, R"({"addr":5,"slot":0,"offset":0,"values":[2114,1234]})", 0x0012, 1234);
  feed_and_wait(feed, R"({"addr":5,"slot":0,"offset":33,"values":[853]})", 0x0011 + 33, 853);
  ASSERT_TRUE(eventually([&] {
    const auto d1 = retained(*broker, "fleet/site-17/D1");
    return d1.contains("fleet/site-17/D1") && Json::parse(d1.at("fleet/site-17/D1"))["oil_temperature"].is_number();
  }, 6000ms));
  const auto found = configs();
  const auto published = retained(*broker, "fleet/site-17/#");
  ASSERT_GT(found.size(), 60u) << daemon->log();
  EXPECT_EQ(count_component(found, "number") + count_component(found, "switch"), 0u) << "commands are off";

  const auto schema = test_support::HomeAssistantSchema::documented();
  std::set<std::string> unique_ids;
  std::size_t binary = 0;
  for (const auto& [topic, config] : found) {
    SCOPED_TRACE(topic);
    // <discovery prefix>/<component>/<node id>/<object id>/config, ids of [a-zA-Z0-9_-].
    EXPECT_TRUE(topic.starts_with("homeassistant/sensor/site-17/") || topic.starts_with("homeassistant/binary_sensor/site-17/"));
    EXPECT_TRUE(topic.ends_with("/config"));
    EXPECT_EQ(topic.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_-/"), std::string::npos);
    ASSERT_TRUE(config.contains("unique_id") && config.contains("name") && config.contains("device"));
    EXPECT_TRUE(unique_ids.insert(config["unique_id"].get<std::string>()).second) << "unique_id twice";
    // Availability: the status topic, and the payload it carries now is the available one.
    EXPECT_EQ(config["availability_topic"], "fleet/site-17/status");
    EXPECT_EQ(published.at("fleet/site-17/status"), config["payload_available"].get<std::string>());
    EXPECT_EQ(config["payload_not_available"], "offline");
    // The state topic is a document the bridge publishes, and the template reaches a key of it.
    const auto state_topic = config["state_topic"].get<std::string>();
    ASSERT_TRUE(published.contains(state_topic));
    const auto document = Json::parse(published.at(state_topic));
    const auto value = template_value(config["value_template"].get<std::string>(), document);
    ASSERT_TRUE(value) << config["value_template"] << " on " << document.dump();
    const auto bank_of_topic = state_topic.substr(state_topic.rfind('/') + 1);
    EXPECT_EQ(*value, document[config["unique_id"].get<std::string>().substr(std::string("site-17_" + bank_of_topic + "_").size())])
        << "the key of its unique id";
    // Home Assistant's documented schema (tests/data): classes, units, categories, keys.
    const auto component_start = std::string_view("homeassistant/").size();
    const auto component = topic.substr(component_start, topic.find('/', component_start) - component_start);
    EXPECT_EQ(schema.violations(component, config), std::vector<std::string>{});
    if (topic.starts_with("homeassistant/binary_sensor/")) {
      ++binary;
      const auto text = jinja_text(*value);
      EXPECT_TRUE(text == config["payload_on"] || text == config["payload_off"] || text == "None") << text;
    }
    // One device per D_N, through the bridge's own; A and B on the bridge's.
    const auto& device = config["device"];
    const auto bank = state_topic.substr(state_topic.rfind('/') + 1);
    if (bank.starts_with("D")) {
      EXPECT_EQ(device["identifiers"], Json::array({"site-17_" + bank}));
      EXPECT_EQ(device["manufacturer"], "UNIMA-KS");
      EXPECT_EQ(device["model"], bank == "D1" ? "unigen-chp" : "uis");
      EXPECT_EQ(device["via_device"], "site-17");
    } else {
      EXPECT_EQ(device["identifiers"], Json::array({"site-17"}));
    }
  }
  EXPECT_GT(binary, 5u);
  // Statistics: generated energy as the energy dashboard takes it; alarms in sight, the
  // other bits diagnostic and disabled; names from the table.
  const auto& energy = found.at("homeassistant/sensor/site-17/D1_generator_energy/config");
  EXPECT_EQ(energy["device_class"], "energy");
  EXPECT_EQ(energy["state_class"], "total_increasing");
  EXPECT_EQ(energy["unit_of_measurement"], "kWh");
  EXPECT_EQ(found.at("homeassistant/binary_sensor/site-17/D1_state_outputs_fault/config")["device_class"], "problem");
  const auto& running = found.at("homeassistant/binary_sensor/site-17/D1_state_outputs_running/config");
  EXPECT_EQ(running["entity_category"], "diagnostic");
  EXPECT_EQ(running["enabled_by_default"], false);
  EXPECT_EQ(found.at("homeassistant/sensor/site-17/D1_oil_temperature/config")["name"], "Teplota oleje") << "UTF-8 through the broker";
  // The values fed, as Home Assistant's templates read them from the real documents.
  const auto d1 = Json::parse(published.at("fleet/site-17/D1"));
  const auto& speed = found.at("homeassistant/sensor/site-17/D1_engine_speed/config");
  EXPECT_EQ(template_value(speed["value_template"].get<std::string>(), d1), Json(1234));
  EXPECT_EQ(speed["unit_of_measurement"], "rpm");
  const auto& power_mode = found.at("homeassistant/binary_sensor/site-17/D1_status_power_mode/config");
  EXPECT_EQ(jinja_text(*template_value(power_mode["value_template"].get<std::string>(), d1)), "True");  // 2114 = 0x0842: bit 11
  const auto a = Json::parse(published.at("fleet/site-17/A"));
  const auto& oil = found.at("homeassistant/sensor/site-17/A_D1_oil_temperature/config");
  EXPECT_EQ(template_value(oil["value_template"].get<std::string>(), a), Json(85.3));
  EXPECT_EQ(oil["unit_of_measurement"], "°C");
  const auto& level = found.at("homeassistant/sensor/site-17/D2_knock_rank_1_level/config");
  EXPECT_EQ(template_value(level["value_template"].get<std::string>(), Json::parse(published.at("fleet/site-17/D2"))), Json(nullptr))
      << "never measured: null, which Home Assistant shows as unknown";
}

// With commands: a number per W register and a switch per X bit, whose commands — as Home
// Assistant sends them — are written like any other.
TEST_F(MqttDiscovery, WAndXEntitiesWithCommandsAndTheirCommandsTakeEffect) {
  config.extra = with_key(config.extra, "commands: true");
  start();
  const auto found = configs();
  EXPECT_EQ(count_component(found, "number"), 16u);
  EXPECT_EQ(count_component(found, "switch"), 16u);
  const auto& w3 = found.at("homeassistant/number/site-17/W_w_03/config");
  EXPECT_EQ(w3["command_topic"], "fleet/site-17/set/W/3");
  EXPECT_EQ(w3["min"], -3276.8);
  EXPECT_EQ(w3["max"], 3276.6) << "3276.7 would be 0x7FFF, not measured";
  EXPECT_EQ(w3["step"], 0.1);
  const auto& x2 = found.at("homeassistant/switch/site-17/X_x_2/config");
  EXPECT_EQ(x2["command_topic"], "fleet/site-17/set/X/2");

  auto feed = feed_client();
  Subscription results(*broker, dir.path() / "results", "fleet/site-17/set/result");
  const auto w3_template = w3["command_template"].get<std::string>();
  publish(*broker, w3["command_topic"].get<std::string>(), home_assistant_renders(w3_template, 12.5));
  EXPECT_TRUE(feed.wait_for_line(R"({"bank":"W","offset":3,"value":125})"));
  publish(*broker, x2["command_topic"].get<std::string>(), x2["payload_on"].get<std::string>());
  EXPECT_TRUE(feed.wait_for_line(R"({"bank":"X","offset":0,"value":4})"));
  ModbusClient client(config.modbus_port);
  EXPECT_EQ(client.read_holding(0x0103, 1), std::vector<std::uint16_t>{125});

  // A finer fraction than the step is refused, not rounded, and W+3 stays as it was; the
  // edges of the range are written.
  ASSERT_TRUE(eventually([&] { return payloads(results.lines(), "fleet/site-17/set/result").size() == 2; })) << results.lines();
  publish(*broker, w3["command_topic"].get<std::string>(), home_assistant_renders(w3_template, 12.34));
  ASSERT_TRUE(eventually([&] { return payloads(results.lines(), "fleet/site-17/set/result").size() == 3; })) << results.lines();
  EXPECT_EQ(Json::parse(payloads(results.lines(), "fleet/site-17/set/result")[2])["ok"], false) << results.lines();
  EXPECT_EQ(client.read_holding(0x0103, 1), std::vector<std::uint16_t>{125});
  publish(*broker, w3["command_topic"].get<std::string>(), home_assistant_renders(w3_template, w3["max"].get<double>()));
  EXPECT_TRUE(feed.wait_for_line(R"({"bank":"W","offset":3,"value":32766})"));
  publish(*broker, w3["command_topic"].get<std::string>(), home_assistant_renders(w3_template, w3["min"].get<double>()));
  EXPECT_TRUE(feed.wait_for_line(R"({"bank":"W","offset":3,"value":32768})"));
  EXPECT_EQ(client.read_holding(0x0103, 1), std::vector<std::uint16_t>{0x8000});
}

// Home Assistant restarted: its birth message `online` on homeassistant/status brings every
// config again.
TEST_F(MqttDiscovery, ConfigsArePublishedAgainWhenHomeAssistantSaysOnline) {
  start();
  const auto found = configs();
  ASSERT_FALSE(found.empty());
  const std::string topic = "homeassistant/sensor/site-17/D1_engine_speed/config";
  Subscription subscription(*broker, dir.path() / "ha", "homeassistant/+/site-17/+/config");
  ASSERT_TRUE(eventually([&] { return payloads(subscription.lines(), topic).size() == 1; })) << "the retained one";
  publish(*broker, "homeassistant/status", "online");
  EXPECT_TRUE(eventually([&] { return payloads(subscription.lines(), topic).size() == 2; })) << subscription.lines();
  EXPECT_EQ(Json::parse(payloads(subscription.lines(), topic).back()), found.at(topic));
  EXPECT_TRUE(eventually([&] {
    return payloads(subscription.lines(), "homeassistant/sensor/site-17/D2_knock_rank_1_level/config").size() == 2;
  })) << "all of them";
}

// A reload that drops D2: its entities are removed (empty retained payloads), D1's stay.
TEST_F(MqttDiscovery, AReloadThatDropsADeviceRemovesItsEntities) {
  start();
  const auto before = configs();
  ASSERT_TRUE(before.contains("homeassistant/sensor/site-17/D2_knock_rank_1_level/config"));
  Subscription subscription(*broker, dir.path() / "ha", "homeassistant/+/site-17/+/config");
  auto yaml = read_file(daemon->config_path());
  const std::string d2 = ", D2: { type: uis, address: 6 }";
  ASSERT_NE(yaml.find(d2), std::string::npos);
  daemon->rewrite_config(yaml.replace(yaml.find(d2), d2.size(), ""));
  daemon->signal(SIGHUP);
  ASSERT_TRUE(eventually([&] { return daemon->log_count("SIGHUP: reloading") == 1; })) << daemon->log();
  EXPECT_TRUE(eventually([&] {
    for (const auto& [topic, payload] : retained(*broker, "homeassistant/#"))
      if (topic.find("/D2_") != std::string::npos) return false;
    return true;
  }, 8000ms)) << daemon->log();
  // Removed by an empty payload each, as Home Assistant's discovery removes an entity.
  const auto removal = payloads(subscription.lines(), "homeassistant/sensor/site-17/D2_knock_rank_1_level/config");
  ASSERT_FALSE(removal.empty()) << subscription.lines();
  EXPECT_TRUE(removal.back().empty() || removal.back() == "(null)") << removal.back();
  const auto after = retained(*broker, "homeassistant/#");
  EXPECT_TRUE(after.contains("homeassistant/sensor/site-17/D1_engine_speed/config"));
  std::size_t d1_before = 0, d1_after = 0;
  for (const auto& [topic, payload] : before) d1_before += topic.find("/D1_") != std::string::npos;
  for (const auto& [topic, payload] : after) d1_after += topic.find("/D1_") != std::string::npos;
  EXPECT_EQ(d1_after, d1_before);
}

}  // namespace
}  // namespace unima::test
