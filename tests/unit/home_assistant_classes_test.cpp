// mqtt/home_assistant_classes and values::display_decimals: what Home Assistant is told a
// value is — device class and state class from the unit and the kind of reading, alarms
// from the table's ids, the precision from the scale — and that the bridge's table of
// classes is within Home Assistant's documented one (tests/data).

#include <gtest/gtest.h>

#include "mqtt/home_assistant_classes.hpp"
#include "tests/support/home_assistant_schema.hpp"
#include "values/value_model.hpp"

namespace unima::mqtt {
namespace {

TEST(HomeAssistantClasses, CountersAreTotalIncreasingQuantitiesMeasurementsCodesNeither) {
  const auto energy = sensor_classes("kWh", Measure::counter);
  EXPECT_EQ(energy.device_class, "energy");
  EXPECT_EQ(energy.state_class, StateClass::total_increasing) << "what the energy dashboard takes";
  const auto hours = sensor_classes("s", Measure::counter);
  EXPECT_EQ(hours.device_class, "duration");
  EXPECT_EQ(hours.state_class, StateClass::total_increasing);
  const auto countdown = sensor_classes("h", Measure::quantity);  // time to service: it falls
  EXPECT_EQ(countdown.device_class, "duration");
  EXPECT_EQ(countdown.state_class, StateClass::measurement);
  const auto code = sensor_classes("", Measure::code);
  EXPECT_EQ(code.device_class, "");
  EXPECT_EQ(code.state_class, StateClass::none);
  EXPECT_EQ(state_class_name(StateClass::total_increasing), "total_increasing");
  EXPECT_EQ(state_class_name(StateClass::measurement), "measurement");
  EXPECT_EQ(state_class_name(StateClass::none), "");
}

TEST(HomeAssistantClasses, ADeviceClassOnlyForAUnitHomeAssistantAcceptsForIt) {
  const std::vector<std::pair<std::string_view, std::string_view>> by_unit = {
      {"°C", "temperature"}, {"kW", "power"},  {"W", "power"},       {"V", "voltage"},   {"mV", "voltage"},
      {"A", "current"},      {"kPa", "pressure"}, {"bar", "pressure"}, {"Hz", "frequency"}, {"mm", "distance"},
      {"VA", "apparent_power"}, {"var", "reactive_power"}, {"h", "duration"}, {"s", "duration"}};
  for (const auto& [unit, device_class] : by_unit) EXPECT_EQ(sensor_classes(unit, Measure::quantity).device_class, device_class) << unit;
  // Ambiguous or classless in Home Assistant: measured, but no class.
  for (const auto unit : {"%", "rpm", "°", "Ω", "", "kvar"}) {
    const auto classes = sensor_classes(unit, Measure::quantity);
    EXPECT_EQ(classes.device_class, "") << unit;
    EXPECT_EQ(classes.state_class, StateClass::measurement) << unit;
  }
  // Energy is a total only: a kWh that is not a counter is no energy sensor (Home
  // Assistant would refuse its statistics), and a power is no counter.
  EXPECT_EQ(sensor_classes("kWh", Measure::quantity).device_class, "");
  EXPECT_EQ(sensor_classes("kW", Measure::counter).device_class, "");
}

// The bridge's table is Home Assistant's: every unit it lists for a class is one Home
// Assistant documents for that class, and every state class it allows is documented too.
TEST(HomeAssistantClasses, TheTableIsWithinHomeAssistantsDocumentedClasses) {
  const auto schema = test_support::HomeAssistantSchema::documented();
  for (const auto& device_class : sensor_device_classes())
    for (const auto unit : device_class.units) {
      SCOPED_TRACE(std::string(device_class.name) + " " + std::string(unit));
      for (const auto state_class : {StateClass::measurement, StateClass::total_increasing}) {
        const bool allowed = state_class == StateClass::measurement ? device_class.allows_measurement : device_class.allows_total_increasing;
        if (!allowed) continue;
        const nlohmann::ordered_json config = {{"unique_id", "u"}, {"device", {{"name", "d"}}}, {"state_topic", "t"},
                                               {"device_class", device_class.name}, {"unit_of_measurement", unit},
                                               {"state_class", state_class_name(state_class)}};
        EXPECT_EQ(schema.violations("sensor", config), std::vector<std::string>{});
      }
    }
}

// The checker itself finds what Home Assistant refuses.
TEST(HomeAssistantClasses, TheSchemaCheckerFindsWhatHomeAssistantRefuses) {
  const auto schema = test_support::HomeAssistantSchema::documented();
  const nlohmann::ordered_json valid = {{"unique_id", "u"}, {"device", {{"name", "d"}}}, {"state_topic", "t"}};
  EXPECT_TRUE(schema.violations("sensor", valid).empty());
  auto wrong_unit = valid;
  wrong_unit["device_class"] = "power";
  wrong_unit["unit_of_measurement"] = "kWh";
  EXPECT_EQ(schema.violations("sensor", wrong_unit).size(), 1u);
  auto energy_measured = valid;
  energy_measured["device_class"] = "energy";
  energy_measured["unit_of_measurement"] = "kWh";
  energy_measured["state_class"] = "measurement";
  EXPECT_EQ(schema.violations("sensor", energy_measured).size(), 1u);
  auto config_category = valid;
  config_category["entity_category"] = "config";
  EXPECT_EQ(schema.violations("sensor", config_category).size(), 1u);
  auto precision = valid;
  precision["suggested_display_precision"] = -1;
  EXPECT_EQ(schema.violations("sensor", precision).size(), 1u);
  auto misspelt = valid;
  misspelt["state_clas"] = "measurement";
  EXPECT_EQ(schema.violations("sensor", misspelt).size(), 1u);
  auto no_topic = valid;
  no_topic.erase("state_topic");
  EXPECT_EQ(schema.violations("sensor", no_topic).size(), 1u);
  auto bit = valid;
  bit["device_class"] = "alarm";
  EXPECT_EQ(schema.violations("binary_sensor", bit).size(), 1u) << "problem is Home Assistant's word";
  bit["device_class"] = "problem";
  EXPECT_TRUE(schema.violations("binary_sensor", bit).empty());
}

TEST(HomeAssistantClasses, AlarmsFromTheWordsOfAlarmsAndProtectionsAndTheIdsThatNameAFault) {
  EXPECT_TRUE(is_alarm_bit("alarm_inputs", "low_oil_pressure"));
  EXPECT_TRUE(is_alarm_bit("alarm_inputs", "central_stop"));
  EXPECT_TRUE(is_alarm_bit("mains_generator_protections", "vector_shift"));
  EXPECT_TRUE(is_alarm_bit("state_outputs", "fault"));
  EXPECT_TRUE(is_alarm_bit("state_outputs", "warning"));
  EXPECT_TRUE(is_alarm_bit("state_outputs", "overspeed_fault"));
  EXPECT_TRUE(is_alarm_bit("state_outputs", "sensor_error"));
  EXPECT_TRUE(is_alarm_bit("control_inputs", "mains_failure"));
  EXPECT_TRUE(is_alarm_bit("status_bits", "collective_alarm"));
  EXPECT_FALSE(is_alarm_bit("state_outputs", "running"));
  EXPECT_FALSE(is_alarm_bit("state_outputs", "ready"));
  EXPECT_FALSE(is_alarm_bit("user_binary_inputs_1_16", "user_binary_input_1"));
  EXPECT_FALSE(is_alarm_bit("status", "power_mode"));
  EXPECT_FALSE(is_alarm_bit("auxiliary_outputs", "acknowledge"));
  EXPECT_FALSE(is_alarm_bit("state_outputs", "faulty_valve")) << "a word of the id, not a part of one";
}

}  // namespace
}  // namespace unima::mqtt

namespace unima::values {
namespace {

ValueDef with_scale(double scale, unsigned decimals) {
  ValueDef def;
  def.scale = scale;
  def.decimals = decimals;
  return def;
}

// The precision a display shows: the scale's step in digits, never the exact decimals a
// reading keeps (0.78125 % steps shown as 35.2 %, not 35.15625 %).
TEST(ValueDisplayDecimals, TheScalesStepNotItsExactDecimals) {
  EXPECT_EQ(display_decimals(with_scale(1, 0)), 0u);
  EXPECT_EQ(display_decimals(with_scale(0.1, 1)), 1u);
  EXPECT_EQ(display_decimals(with_scale(0.01, 2)), 2u);
  EXPECT_EQ(display_decimals(with_scale(0.001, 3)), 3u);
  EXPECT_EQ(display_decimals(with_scale(0.78125, 5)), 1u);
  EXPECT_EQ(display_decimals(with_scale(0.097656, 6)), 2u);
  EXPECT_EQ(display_decimals(with_scale(0.00244, 5)), 3u);
  EXPECT_EQ(display_decimals(with_scale(0.5, 1)), 1u);
  EXPECT_EQ(display_decimals(with_scale(10, 0)), 0u);
}

}  // namespace
}  // namespace unima::values
