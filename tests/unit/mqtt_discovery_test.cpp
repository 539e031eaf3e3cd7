// mqtt::discovery_messages (SPEC §15): Home Assistant's discovery configs of a config's
// values — their topics, unique ids, templates on the real bank documents, units, devices
// — and W/X entities only with commands; `mqtt.discovery` as the config reads it.

#include <gtest/gtest.h>

#include <map>
#include <set>

#include "banks/table_catalog.hpp"
#include "config/config.hpp"
#include "mqtt/bank_documents.hpp"
#include "mqtt/discovery.hpp"
#include "tests/support/error_message.hpp"
#include "tests/support/home_assistant_template.hpp"
#include "values/store_snapshot.hpp"

namespace unima::mqtt {
namespace {

using banks::BankId;
using Json = nlohmann::ordered_json;
using test_support::jinja_text;
using test_support::template_value;

const std::string site_mqtt = "mqtt: { broker: 'mqtt://127.0.0.1', client_id: site-17.b, topic: fleet/site-17, discovery: {} }\n";
const std::string chp_and_uis =
    "devices: { D1: { type: unigen-chp, address: 5 }, D2: { type: uis, address: 6 } }\n"
    "mapping: { A: [ D1.oil_temperature ], B: [ D1+0x11.7, X.2 ] }\n";

config::Config site(const std::string& yaml) { return config::load_text(yaml, "bridge.yaml"); }

// The configs by their topics, each payload parsed.
std::map<std::string, Json> configs_of(const config::Config& config) {
  std::map<std::string, Json> configs;
  for (const auto& message : discovery_messages(config, values::ValueModel(config)))
    EXPECT_TRUE(configs.emplace(message.topic, Json::parse(message.payload)).second) << "twice: " << message.topic;
  return configs;
}

std::size_t count_component(const std::map<std::string, Json>& configs, const std::string& component) {
  std::size_t count = 0;
  for (const auto& [topic, payload] : configs) count += topic.starts_with("homeassistant/" + component + "/");
  return count;
}

TEST(MqttDiscovery, ASensorPerValueOnItsBankDocumentWithItsUnitAndDevice) {
  const auto configs = configs_of(site(chp_and_uis + site_mqtt));
  ASSERT_TRUE(configs.contains("homeassistant/sensor/site-17_b/D1_engine_speed/config"));
  const auto& speed = configs.at("homeassistant/sensor/site-17_b/D1_engine_speed/config");
  EXPECT_EQ(speed["name"], "engine_speed");
  EXPECT_EQ(speed["unique_id"], "site-17.b_D1_engine_speed") << "<client_id>_<bank>_<identifier>";
  EXPECT_EQ(speed["state_topic"], "fleet/site-17/D1");
  EXPECT_EQ(speed["value_template"], "{{ value_json['engine_speed'] }}");
  EXPECT_EQ(speed["unit_of_measurement"], "rpm") << "the table's min-1 as Home Assistant writes it";
  EXPECT_EQ(speed["suggested_display_precision"], 0);
  EXPECT_EQ(speed["availability_topic"], "fleet/site-17/status");
  EXPECT_EQ(speed["payload_available"], "online");
  EXPECT_EQ(speed["payload_not_available"], "offline");
  EXPECT_EQ(speed["device"], Json::parse(R"({"identifiers":["site-17.b_D1"],"name":"site-17.b D1","model":"unigen-chp",
                                              "manufacturer":"UNIMA-KS","via_device":"site-17.b"})"));

  const auto& oil = configs.at("homeassistant/sensor/site-17_b/D1_oil_temperature/config");
  EXPECT_EQ(oil["unit_of_measurement"], "°C");
  EXPECT_EQ(oil["suggested_display_precision"], 1) << "tenths";
  // A byte pair's byte: a dotted key, reached whole by the bracketed form; its own unit.
  const auto& level = configs.at("homeassistant/sensor/site-17_b/D2_knock_rank_1_level/config");
  EXPECT_EQ(level["value_template"], "{{ value_json['knock_rank_1.level'] }}");
  EXPECT_EQ(level["unit_of_measurement"], "%");
  EXPECT_EQ(level["device"]["model"], "uis");
  EXPECT_EQ(level["device"]["identifiers"], Json::array({"site-17.b_D2"}));
  // One value for a 32-bit pair, nothing for its halves or for reserves.
  EXPECT_TRUE(configs.contains("homeassistant/sensor/site-17_b/D1_operating_hours/config"));
  for (const auto& [topic, payload] : configs) {
    EXPECT_EQ(topic.find("_low/"), std::string::npos) << topic;
    EXPECT_EQ(topic.find("reserve"), std::string::npos) << topic;
  }
}

TEST(MqttDiscovery, BitsAreBinarySensorsWhoseTemplateRendersTheirPayloads) {
  const auto configs = configs_of(site(chp_and_uis + site_mqtt));
  const auto& power_mode = configs.at("homeassistant/binary_sensor/site-17_b/D1_status_power_mode/config");
  EXPECT_EQ(power_mode["value_template"], "{{ value_json['status.power_mode'] }}");
  EXPECT_EQ(power_mode["payload_on"], "True");
  EXPECT_EQ(power_mode["payload_off"], "False");
  EXPECT_FALSE(power_mode.contains("unit_of_measurement"));
  for (const auto& [value, text] : {std::pair{Json(true), "True"}, {Json(false), "False"}, {Json(nullptr), "None"}})
    EXPECT_EQ(jinja_text(*template_value(power_mode["value_template"].get<std::string>(), Json{{"status.power_mode", value}})), text);
  // A field of several bits is a number, the word as a whole too.
  EXPECT_TRUE(configs.contains("homeassistant/sensor/site-17_b/D1_status_unit_mode/config"));
  EXPECT_TRUE(configs.contains("homeassistant/sensor/site-17_b/D1_status/config"));
}

// A and B: on the bridge's device, keyed by their mapping sources; unmapped entries none.
TEST(MqttDiscovery, AAndBEntriesByTheirSourcesOnTheBridgesDevice) {
  const auto configs = configs_of(site(chp_and_uis + site_mqtt));
  const auto& a = configs.at("homeassistant/sensor/site-17_b/A_D1_oil_temperature/config");
  EXPECT_EQ(a["unique_id"], "site-17.b_A_D1.oil_temperature");
  EXPECT_EQ(a["state_topic"], "fleet/site-17/A");
  EXPECT_EQ(a["value_template"], "{{ value_json['D1.oil_temperature'] }}");
  EXPECT_EQ(a["unit_of_measurement"], "°C");
  EXPECT_EQ(a["device"], Json::parse(R"({"identifiers":["site-17.b"],"name":"site-17.b","model":"unima-bridge"})"));
  std::size_t a_configs = 0;
  for (const auto& [topic, payload] : configs) a_configs += payload.value("state_topic", "") == "fleet/site-17/A";
  EXPECT_EQ(a_configs, 1u) << "the 15 unmapped entries are not published";

  const auto& bit = configs.at("homeassistant/binary_sensor/site-17_b/B_D1_0x11_7/config");
  EXPECT_EQ(bit["value_template"], "{{ value_json['D1+0x11.7'] }}");
  // X.2 is absent from B's document until a master writes X: unknown then, not an error.
  const auto& x = configs.at("homeassistant/binary_sensor/site-17_b/B_X_2/config");
  EXPECT_EQ(x["value_template"], "{{ value_json['X.2'] | default(none) }}");
  EXPECT_EQ(template_value(x["value_template"].get<std::string>(), Json{{"online", true}}), Json(nullptr));
}

// Every template reaches its value in the document as mqtt/bank_documents makes it, for
// every value published: the keys are the document's own.
TEST(MqttDiscovery, EveryTemplateReachesItsValueInTheRealDocument) {
  const auto config = site(chp_and_uis + site_mqtt);
  const values::ValueModel model(config);
  banks::RegisterStore store(config::bank_shapes(config));
  store.set_mapping(config.mapping);
  store.set_online(BankId::D1, true);
  store.set_online(BankId::D2, true);
  const std::vector<std::uint16_t> d1 = {0x0842, 1500, 0x0010, 0x0002};
  store.store_telegram(BankId::D1, 0, d1);
  const std::vector<std::uint16_t> knock = {16 << 8 | 3};
  store.store_telegram(BankId::D2, 0x08, knock);
  const auto snapshot = values::snapshot_of(store);
  std::map<std::string, Json> documents;
  for (const auto bank : published_banks(model))
    documents["fleet/site-17/" + std::string(banks::bank_name(bank))] =
        bank_document(*model.bank(bank), model.evaluate(bank, snapshot), snapshot[banks::index_of(bank)].online, {});

  std::size_t reached = 0;
  for (const auto& [topic, payload] : configs_of(config)) {
    if (!payload.contains("state_topic")) continue;
    ASSERT_TRUE(documents.contains(payload["state_topic"].get<std::string>())) << topic;
    const auto& document = documents.at(payload["state_topic"].get<std::string>());
    const auto value = template_value(payload["value_template"].get<std::string>(), document);
    ASSERT_TRUE(value) << topic << " " << payload["value_template"] << " on " << document.dump();
    ++reached;
  }
  EXPECT_GT(reached, 60u);
  const auto& d1_document = documents.at("fleet/site-17/D1");
  EXPECT_EQ(template_value(std::string("{{ value_json['engine_speed'] }}"), d1_document), Json(1500));
  EXPECT_EQ(template_value(std::string("{{ value_json['status.unit_mode'] }}"), d1_document), Json(0));
  EXPECT_EQ(template_value(std::string("{{ value_json['status.power_mode'] }}"), d1_document), Json(true));
}

TEST(MqttDiscovery, WNumbersAndXSwitchesOnlyWithCommands) {
  const auto without = configs_of(site(chp_and_uis + site_mqtt));
  EXPECT_EQ(count_component(without, "number"), 0u);
  EXPECT_EQ(count_component(without, "switch"), 0u);

  auto with_commands = site_mqtt;
  with_commands.replace(with_commands.find("discovery"), 0, "commands: true, ");
  const auto configs = configs_of(site(chp_and_uis + with_commands));
  EXPECT_EQ(count_component(configs, "number"), 16u);
  EXPECT_EQ(count_component(configs, "switch"), 16u);
  const auto& w3 = configs.at("homeassistant/number/site-17_b/W_w_03/config");
  EXPECT_EQ(w3["unique_id"], "site-17.b_W_w_03");
  EXPECT_EQ(w3["command_topic"], "fleet/site-17/set/W/3");
  EXPECT_EQ(w3["command_template"],
            "{% set raw = value / 0.1 %}{{ (raw | round | int) if (raw - raw | round) | abs < 0.000001 else value }}")
      << "W holds tenths; the topic takes the register, and a finer fraction goes as it is, to be refused";
  // The range and step of the value codec (values/value_codec): 3276.7 would be 0x7FFF.
  EXPECT_EQ(w3["min"].get<double>(), -3276.8);
  EXPECT_EQ(w3["max"].get<double>(), 3276.6);
  EXPECT_EQ(w3["step"].get<double>(), 0.1);
  EXPECT_EQ(w3["min"].dump(), "-3276.8") << "as a reading is written, not -3276.8000000000002";
  EXPECT_EQ(w3["max"].dump(), "3276.6");
  EXPECT_EQ(w3["retain"], false);
  EXPECT_FALSE(w3.contains("state_topic")) << "W is not published: optimistic";
  EXPECT_EQ(w3["device"]["identifiers"], Json::array({"site-17.b"}));
  const auto& x15 = configs.at("homeassistant/switch/site-17_b/X_x_15/config");
  EXPECT_EQ(x15["command_topic"], "fleet/site-17/set/X/15");
  EXPECT_EQ(x15["payload_on"], "1");
  EXPECT_EQ(x15["payload_off"], "0");
  EXPECT_EQ(x15["availability_topic"], "fleet/site-17/status");
  // One switch per bit the value model gives X (x.0 … x.15), its topic the bit's number.
  EXPECT_EQ(configs.at("homeassistant/switch/site-17_b/X_x_0/config")["command_topic"], "fleet/site-17/set/X/0");
  EXPECT_FALSE(configs.contains("homeassistant/switch/site-17_b/X_x/config")) << "the word is no switch";
}

TEST(MqttDiscovery, NoneWithoutDiscoveryAndTheConfiguredPrefix) {
  EXPECT_TRUE(configs_of(site(chp_and_uis + "mqtt: { broker: 'mqtt://127.0.0.1' }\n")).empty());
  EXPECT_TRUE(configs_of(site(chp_and_uis)).empty());
  const auto config = site(chp_and_uis + "mqtt: { broker: 'mqtt://127.0.0.1', client_id: b, discovery: { prefix: ha/site } }\n");
  EXPECT_EQ(home_assistant_status_topic(config), "ha/site/status");
  for (const auto& message : discovery_messages(config, values::ValueModel(config)))
    EXPECT_TRUE(message.topic.starts_with("ha/site/")) << message.topic;
}

TEST(MqttDiscovery, AReloadWithdrawsWhatTheNewConfigNoLongerServes) {
  const auto before_config = site(chp_and_uis + site_mqtt);
  const auto after_config = site("devices: { D1: { type: unigen-chp, address: 5 } }\n" + site_mqtt);
  const auto before = discovery_messages(before_config, values::ValueModel(before_config));
  const auto after = discovery_messages(after_config, values::ValueModel(after_config));
  const auto withdrawn = withdrawn_topics(before, after);
  ASSERT_FALSE(withdrawn.empty());
  for (const auto& topic : withdrawn)
    EXPECT_TRUE(topic.find("/D2_") != std::string::npos || topic.find("/A_") != std::string::npos ||
                topic.find("/B_") != std::string::npos)
        << topic;
  EXPECT_NE(std::find(withdrawn.begin(), withdrawn.end(), "homeassistant/sensor/site-17_b/D2_knock_rank_1_level/config"),
            withdrawn.end());
  EXPECT_TRUE(withdrawn_topics(after, after).empty());
}

// Every device type: topics and unique ids one per value, ids of Home Assistant's characters.
TEST(MqttDiscovery, EveryDeviceTypesTopicsAndUniqueIdsAreUniqueAndSafe) {
  for (const auto type : banks::device_type_ids()) {
    const auto config = site("devices: { D1: { type: " + std::string(type) + ", address: 5 } }\n" + site_mqtt);
    std::set<std::string> unique_ids;
    for (const auto& [topic, payload] : configs_of(config)) {
      EXPECT_TRUE(unique_ids.insert(payload["unique_id"].get<std::string>()).second) << type << ": " << payload["unique_id"];
      const auto object_id = topic.substr(0, topic.rfind('/'));
      EXPECT_EQ(object_id.substr(object_id.rfind('/') + 1), discovery_id(object_id.substr(object_id.rfind('/') + 1))) << topic;
    }
    EXPECT_FALSE(unique_ids.empty()) << type;
  }
}

TEST(MqttDiscovery, UnitsAndIdsAsHomeAssistantWritesThem) {
  EXPECT_EQ(home_assistant_unit("min-1"), "rpm");
  EXPECT_EQ(home_assistant_unit("kVAr"), "kvar");
  for (const auto unit : {"°C", "%", "kW", "kWh", "V", "A", "h", "s", "kPa", "bar"}) EXPECT_EQ(home_assistant_unit(unit), unit);
  EXPECT_EQ(discovery_id("site 17.b/+#"), "site_17_b___");
  EXPECT_EQ(discovery_id("D1_knock-rank_1"), "D1_knock-rank_1");
}

TEST(MqttDiscoveryConfig, OffUnlessGivenAPrefixOfHomeAssistantByDefault) {
  EXPECT_FALSE(site("mqtt: { broker: 'mqtt://x' }\n").mqtt->discovery);
  EXPECT_EQ(site("mqtt: { broker: 'mqtt://x', discovery: {} }\n").mqtt->discovery->prefix, "homeassistant");
  EXPECT_EQ(site("mqtt:\n  broker: 'mqtt://x'\n  discovery:\n").mqtt->discovery->prefix, "homeassistant");
  EXPECT_EQ(site("mqtt: { broker: 'mqtt://x', discovery: { prefix: ha/site-17 } }\n").mqtt->discovery->prefix, "ha/site-17");
  const auto error = [](const std::string& yaml) {
    return test_support::error_message<config::ConfigError>([&] { (void)config::load_text(yaml, "cfg.yaml"); });
  };
  EXPECT_EQ(error("mqtt: { broker: 'mqtt://x', discovery: true }\n"),
            "cfg.yaml:1:40: mqtt.discovery must be a mapping, e.g. { prefix: homeassistant }");
  EXPECT_EQ(error("mqtt: { broker: 'mqtt://x', discovery: { prefix: 'ha/#' } }\n"),
            "cfg.yaml:1:50: mqtt.discovery.prefix must be a topic prefix without wildcards (# +) or a leading or trailing /");
  EXPECT_EQ(error("mqtt: { broker: 'mqtt://x', discovery: { prefix: '' } }\n"),
            "cfg.yaml:1:50: mqtt.discovery.prefix must be a topic prefix without wildcards (# +) or a leading or trailing /");
  EXPECT_EQ(error("mqtt: { broker: 'mqtt://x', discovery: { topic: ha } }\n"),
            "cfg.yaml:1:42: unknown key 'topic' in mqtt.discovery (known: prefix)");
}

}  // namespace
}  // namespace unima::mqtt
