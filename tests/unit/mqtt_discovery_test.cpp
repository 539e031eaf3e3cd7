// mqtt::discovery_messages (SPEC §15): Home Assistant's discovery configs of a config's
// values — their topics, unique ids, templates on the real bank documents, units, devices
// — and W/X entities only with commands; `mqtt.discovery` as the config reads it.

#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "banks/table_catalog.hpp"
#include "config/config.hpp"
#include "mqtt/bank_documents.hpp"
#include "mqtt/discovery.hpp"
#include "tests/support/error_message.hpp"
#include "tests/support/home_assistant_schema.hpp"
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
  EXPECT_EQ(speed["name"], "Otáčky") << "the table's label";
  EXPECT_EQ(speed["default_entity_id"], "sensor.site_17_b_d1_engine_speed") << "the entity id of the name it had";
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

// The demo's config (config/examples/demo.yaml: a CHP unit, its USC and UVR) with
// discovery and commands: everything the bridge would publish for it.
config::Config demo_with_discovery() {
  std::ifstream file(std::string(UNIMA_SOURCE_DIR) + "/config/examples/demo.yaml");
  std::stringstream text;
  text << file.rdbuf();
  return site(text.str() + "mqtt: { broker: 'mqtt://127.0.0.1', client_id: site-17.b, commands: true, discovery: {} }\n");
}

std::string component_of(const std::string& topic) {
  const auto start = topic.find('/') + 1;
  return topic.substr(start, topic.find('/', start) - start);
}

// Home Assistant's documented schema (tests/data) over every config of the demo and of
// every device type: each is one Home Assistant takes.
TEST(MqttDiscoverySchema, EveryConfigOfTheDemoAndOfEveryDeviceTypeIsValid) {
  const auto schema = test_support::HomeAssistantSchema::documented();
  const auto demo = configs_of(demo_with_discovery());
  ASSERT_GT(demo.size(), 300u);
  for (const auto& [topic, payload] : demo) EXPECT_EQ(schema.violations(component_of(topic), payload), std::vector<std::string>{}) << topic;
  for (const auto type : banks::device_type_ids()) {
    const auto config = site("devices: { D1: { type: " + std::string(type) + ", address: 5 } }\n" + site_mqtt);
    for (const auto& [topic, payload] : configs_of(config))
      EXPECT_EQ(schema.violations(component_of(topic), payload), std::vector<std::string>{}) << type << ": " << topic;
  }
}

// Long-term statistics: a counter is total_increasing — generated energy the energy
// dashboard takes (energy, kWh) — a measured value is a measurement, a state neither.
TEST(MqttDiscoverySchema, CountersAreTotalsMeasuredValuesMeasurementsStatesNeither) {
  const auto configs = configs_of(site(chp_and_uis + site_mqtt));
  const auto sensor = [&](const std::string& object_id) { return configs.at("homeassistant/sensor/site-17_b/" + object_id + "/config"); };
  const auto energy = sensor("D1_generator_energy");
  EXPECT_EQ(energy["device_class"], "energy");
  EXPECT_EQ(energy["state_class"], "total_increasing");
  EXPECT_EQ(energy["unit_of_measurement"], "kWh");
  EXPECT_EQ(energy["suggested_display_precision"], 1);
  const auto hours = sensor("D1_operating_hours");
  EXPECT_EQ(hours["device_class"], "duration");
  EXPECT_EQ(hours["state_class"], "total_increasing");
  EXPECT_EQ(hours["unit_of_measurement"], "s");
  const auto to_service = sensor("D1_time_to_service");
  EXPECT_EQ(to_service["device_class"], "duration");
  EXPECT_EQ(to_service["state_class"], "measurement") << "it counts down";
  const auto oil = sensor("D1_oil_temperature");
  EXPECT_EQ(oil["device_class"], "temperature");
  EXPECT_EQ(oil["state_class"], "measurement");
  EXPECT_EQ(sensor("D1_generator_active_power")["device_class"], "power");
  const auto speed = sensor("D1_engine_speed");
  EXPECT_FALSE(speed.contains("device_class")) << "Home Assistant has no class for rpm";
  EXPECT_EQ(speed["state_class"], "measurement");
  EXPECT_FALSE(sensor("D1_generator_reactive_power").contains("device_class")) << "kvar: not in every Home Assistant";
  const auto knock = sensor("D2_knock_rank_1_level");
  EXPECT_FALSE(knock.contains("device_class")) << "% is no one class";
  EXPECT_EQ(knock["state_class"], "measurement");
  for (const auto* state : {"D1_status", "D1_status_unit_mode", "D1_alarm_inputs"}) {
    EXPECT_FALSE(sensor(state).contains("state_class")) << state << ": a state, no statistics of it";
    EXPECT_FALSE(sensor(state).contains("device_class")) << state;
  }
  const auto a = sensor("A_D1_oil_temperature");
  EXPECT_EQ(a["device_class"], "temperature") << "an entry of A is its source's quantity";
  EXPECT_EQ(a["state_class"], "measurement");
  std::size_t with_state_class = 0;
  for (const auto& [topic, payload] : configs) with_state_class += payload.contains("state_class");
  EXPECT_GT(with_state_class, 100u);
}

// A D_N's named bit is a diagnostic entity, disabled by default, unless it is an alarm
// or a fault, which stays in sight as a problem; B's mapped bits stay in sight.
TEST(MqttDiscoverySchema, BitsAreDiagnosticAndDisabledExceptAlarms) {
  const auto configs = configs_of(demo_with_discovery());
  std::size_t alarms = 0, diagnostic = 0;
  for (const auto& [topic, payload] : configs) {
    if (component_of(topic) != "binary_sensor") continue;
    SCOPED_TRACE(topic);
    if (payload.value("device_class", "") == "problem") {
      ++alarms;
      EXPECT_FALSE(payload.contains("entity_category"));
      EXPECT_FALSE(payload.contains("enabled_by_default")) << "enabled, Home Assistant's default";
    } else {
      ++diagnostic;
      EXPECT_EQ(payload["entity_category"], "diagnostic");
      EXPECT_EQ(payload["enabled_by_default"], false);
    }
  }
  // The CHP unit's 16 alarm inputs, 14 protections, fault, warning and mains failure; the
  // USC's 4 faults, the UVR's 6: 43 in sight of 217.
  EXPECT_EQ(alarms, 43u);
  EXPECT_EQ(diagnostic, 174u);
  const auto bit = [&](const std::string& object_id) { return configs.at("homeassistant/binary_sensor/site-17_b/" + object_id + "/config"); };
  EXPECT_EQ(bit("D1_state_outputs_fault")["device_class"], "problem");
  EXPECT_EQ(bit("D1_state_outputs_warning")["device_class"], "problem");
  EXPECT_EQ(bit("D1_alarm_inputs_low_oil_pressure")["device_class"], "problem") << "an alarm input";
  EXPECT_EQ(bit("D1_mains_generator_protections_generator_overcurrent")["device_class"], "problem") << "a protection";
  EXPECT_EQ(bit("D2_state_outputs_overspeed_fault")["device_class"], "problem");
  EXPECT_EQ(bit("D3_state_outputs_undervoltage_fault")["device_class"], "problem");
  EXPECT_EQ(bit("D1_state_outputs_running")["entity_category"], "diagnostic");
  EXPECT_EQ(bit("D1_user_binary_inputs_1_16_user_binary_input_1")["enabled_by_default"], false);
  EXPECT_EQ(bit("D1_status_power_mode")["enabled_by_default"], false);
  // B: what the integrator mapped stays enabled; a mapped alarm is a problem.
  const auto b = configs_of(site(chp_and_uis + site_mqtt)).at("homeassistant/binary_sensor/site-17_b/B_D1_0x11_7/config");
  EXPECT_FALSE(b.contains("enabled_by_default"));
  EXPECT_FALSE(b.contains("entity_category"));
  const auto b_fault = configs_of(site("devices: { D1: { type: unigen-chp, address: 5 } }\nmapping: { B: [ D1.fault ] }\n" + site_mqtt))
                           .at("homeassistant/binary_sensor/site-17_b/B_D1_fault/config");
  EXPECT_EQ(b_fault["device_class"], "problem");
}

// The precision a sensor shows is its scale's step (0.1 -> 1, 0.01 -> 2, 1 -> 0), never
// more decimals than the scale has — for every value of every device type.
TEST(MqttDiscoverySchema, PrecisionIsTheScalesStepNeverMoreThanItsDecimals) {
  std::size_t checked = 0;
  for (const auto type : banks::device_type_ids()) {
    const auto config = site("devices: { D1: { type: " + std::string(type) + ", address: 5 } }\n" + site_mqtt);
    const auto configs = configs_of(config);
    const values::ValueModel model(config);
    for (const auto& layout : model.banks())
      for (const auto& def : layout.values) {
        const auto topic = "homeassistant/sensor/site-17_b/" + discovery_id(std::string(banks::bank_name(layout.bank)) + "_" + def.name) + "/config";
        if (!configs.contains(topic) || !configs.at(topic).contains("suggested_display_precision")) continue;
        const auto precision = configs.at(topic)["suggested_display_precision"].get<unsigned>();
        EXPECT_LE(precision, def.decimals) << topic << " scale " << def.scale;
        EXPECT_EQ(precision, values::display_decimals(def)) << topic;
        ++checked;
      }
  }
  EXPECT_GT(checked, 300u);
  const auto configs = configs_of(site(chp_and_uis + site_mqtt));
  EXPECT_EQ(configs.at("homeassistant/sensor/site-17_b/D2_knock_rank_1_level/config")["suggested_display_precision"], 1)
      << "0.78125 % steps: 35.2 %, not 35.15625 %";
  EXPECT_EQ(configs.at("homeassistant/sensor/site-17_b/D1_engine_speed/config")["suggested_display_precision"], 0);
  const auto demo = configs_of(demo_with_discovery());
  EXPECT_EQ(demo.at("homeassistant/sensor/site-17_b/D3_load_current/config")["suggested_display_precision"], 3) << "0.001 A";
  for (const auto& [topic, payload] : demo) EXPECT_LT(payload.value("suggested_display_precision", 0), 4) << topic;
}

// Names a person reads — the table's labels — while unique ids, topics and entity ids
// stay those of the document's keys.
TEST(MqttDiscoverySchema, NamesAreTheTablesLabelsIdsStayTheKeys) {
  const auto configs = configs_of(site(chp_and_uis + site_mqtt));
  const auto at = [&](const std::string& component, const std::string& object_id) {
    return configs.at("homeassistant/" + component + "/site-17_b/" + object_id + "/config");
  };
  EXPECT_EQ(at("sensor", "D1_oil_temperature")["name"], "Teplota oleje");
  EXPECT_EQ(at("sensor", "D1_operating_hours")["name"], "Motohodiny") << "the pair's quantity";
  EXPECT_EQ(at("sensor", "D2_knock_rank_1_level")["name"], "První nejvyšší úroveň detonací");
  const auto power_mode = at("binary_sensor", "D1_status_power_mode");
  EXPECT_EQ(power_mode["name"], "Režim výkonu (0=MAN, 1=COPY)");
  EXPECT_EQ(power_mode["default_entity_id"], "binary_sensor.site_17_b_d1_status_power_mode");
  EXPECT_EQ(power_mode["unique_id"], "site-17.b_D1_status.power_mode");
  // A label several values share says which value it is.
  EXPECT_EQ(at("sensor", "D1_control_inputs")["name"], "Binární vstupy (control_inputs)");
  EXPECT_EQ(at("sensor", "D1_status")["name"], "Stav (status)");
  EXPECT_EQ(at("sensor", "D1_status_state")["name"], "Stav (status.state)");
  // A's entry shows another device's value: its source says which.
  const auto a = at("sensor", "A_D1_oil_temperature");
  EXPECT_EQ(a["name"], "Teplota oleje (D1.oil_temperature)");
  EXPECT_EQ(a["default_entity_id"], "sensor.site_17_b_d1_oil_temperature");
  EXPECT_EQ(at("binary_sensor", "B_D1_0x11_7")["name"], "D1+0x11.7") << "no label: the key";
  // Within a device, no two names alike.
  std::map<std::string, std::set<std::string>> names;
  for (const auto& [topic, payload] : configs)
    EXPECT_TRUE(names[payload["device"]["name"].get<std::string>()].insert(payload["name"].get<std::string>()).second)
        << topic << " " << payload["name"];
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
