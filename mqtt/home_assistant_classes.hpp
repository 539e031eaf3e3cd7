#pragma once
// What Home Assistant is told a value is, beside its unit and name (SPEC §15, issue 44):
// a sensor's `device_class` and `state_class` — which decide whether Home Assistant keeps
// long-term statistics and whether the energy dashboard can use a value — and whether a
// bit is an alarm that stays in sight or a detail for the diagnostic list. Pure: from the
// unit, what kind of reading a value is and the table's ids; mqtt/discovery writes them
// into the configs.
//
// The classes are Home Assistant's documented ones, with the units it accepts for each
// (its MQTT sensor refuses a whole config whose unit does not fit its device class):
//   https://developers.home-assistant.io/docs/core/entity/sensor/ ("Available device classes",
//   "Available state classes")
//   https://www.home-assistant.io/integrations/sensor/ ("Device class")
//   https://www.home-assistant.io/integrations/binary_sensor/ ("Device class": problem)

#include <span>
#include <string_view>

namespace unima::mqtt {

/// What a value is to Home Assistant's statistics.
enum class Measure {
  code,      // a bit word, a field of several bits, characters: a state, not a quantity
  quantity,  // measured now (a temperature, a power): statistics of its mean, min, max
  counter,   // a running total that only grows (operating hours, energy generated)
};

enum class StateClass { none, measurement, total_increasing };

std::string_view state_class_name(StateClass state_class);  // "" for none

/// One of Home Assistant's sensor device classes that a unit of the device tables names:
/// the units Home Assistant accepts for it and the state classes it allows.
struct SensorDeviceClass {
  std::string_view name;
  std::span<const std::string_view> units;
  bool allows_measurement = true;
  bool allows_total_increasing = false;
};

/// Every class a value may be given, in the order a unit is looked up (a unit is in one
/// only). Classes whose units are ambiguous in the tables are not there: `%` (battery,
/// humidity, moisture, power factor), `°` (wind direction), a value without a unit.
std::span<const SensorDeviceClass> sensor_device_classes();

struct SensorClasses {
  std::string_view device_class;  // "" for none
  StateClass state_class = StateClass::none;
};

/// The classes of a sensor of unit `home_assistant_unit` (as mqtt::home_assistant_unit
/// writes it) measuring `measure`: a counter is `total_increasing`, a quantity
/// `measurement`, a code neither; the device class whose units hold the unit, when that
/// class allows the state class (so energy only for a counter: the energy dashboard takes
/// energy, total_increasing, kWh).
SensorClasses sensor_classes(std::string_view home_assistant_unit, Measure measure);

/// Whether one named bit of a table's bit word is an alarm or a fault, from the table's
/// ids: a bit of a word the seed gives to alarms or protections (`alarm_inputs`,
/// `mains_generator_protections`), or a bit whose id names a fault, alarm, warning, error
/// or failure (`fault`, `overspeed_fault`, `sensor_error`, `mains_failure`). Such a bit is
/// a `problem` binary sensor in sight; every other bit is a diagnostic one, disabled
/// until a person enables it.
bool is_alarm_bit(std::string_view word_id, std::string_view field_id);

}  // namespace unima::mqtt
