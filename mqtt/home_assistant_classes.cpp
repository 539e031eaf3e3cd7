#include "mqtt/home_assistant_classes.hpp"

#include <algorithm>
#include <array>

namespace unima::mqtt {

namespace {

using namespace std::string_view_literals;

// Home Assistant's documented units per device class (the pages in the header), those that
// its releases of the last years all accept: a unit added lately (`kvar` for
// reactive_power) would make an older Home Assistant refuse the whole entity, so a value in
// it gets no device class and is still shown, with its unit and statistics.
constexpr std::array temperature_units{"°C"sv, "°F"sv, "K"sv};
constexpr std::array power_units{"W"sv, "kW"sv};
constexpr std::array energy_units{"Wh"sv, "kWh"sv, "MWh"sv};
constexpr std::array duration_units{"d"sv, "h"sv, "min"sv, "s"sv};
constexpr std::array voltage_units{"V"sv, "mV"sv};
constexpr std::array current_units{"A"sv, "mA"sv};
constexpr std::array frequency_units{"Hz"sv, "kHz"sv, "MHz"sv, "GHz"sv};
constexpr std::array pressure_units{"Pa"sv, "hPa"sv, "kPa"sv, "mbar"sv, "cbar"sv, "bar"sv, "mmHg"sv, "inHg"sv, "psi"sv};
constexpr std::array apparent_power_units{"VA"sv};
constexpr std::array reactive_power_units{"var"sv};
constexpr std::array distance_units{"km"sv, "m"sv, "cm"sv, "mm"sv, "mi"sv, "yd"sv, "ft"sv, "in"sv};

// name, units, allows measurement, allows total_increasing — as Home Assistant's
// DEVICE_CLASS_STATE_CLASSES lists them: energy is a total only; duration and distance
// may be either; the rest are measurements.
constexpr std::array classes{
    SensorDeviceClass{"temperature", temperature_units, true, false},
    SensorDeviceClass{"power", power_units, true, false},
    SensorDeviceClass{"energy", energy_units, false, true},
    SensorDeviceClass{"duration", duration_units, true, true},
    SensorDeviceClass{"voltage", voltage_units, true, false},
    SensorDeviceClass{"current", current_units, true, false},
    SensorDeviceClass{"frequency", frequency_units, true, false},
    SensorDeviceClass{"pressure", pressure_units, true, false},
    SensorDeviceClass{"apparent_power", apparent_power_units, true, false},
    SensorDeviceClass{"reactive_power", reactive_power_units, true, false},
    SensorDeviceClass{"distance", distance_units, true, true},
};

bool allows(const SensorDeviceClass& device_class, StateClass state_class) {
  switch (state_class) {
    case StateClass::measurement: return device_class.allows_measurement;
    case StateClass::total_increasing: return device_class.allows_total_increasing;
    case StateClass::none: return true;
  }
  return false;
}

// The seed's words of alarm inputs and of mains and generator protections: every bit of
// them is an alarm when set.
constexpr std::array alarm_words{"alarm_inputs"sv, "mains_generator_protections"sv};
// Words of a bit's id that name a fault state (`overspeed_fault`, `mains_failure_l1`).
constexpr std::array alarm_id_words{"fault"sv, "alarm"sv, "warning"sv, "error"sv, "failure"sv};

bool has_id_word(std::string_view id, std::string_view word) {
  for (std::size_t start = 0; start <= id.size();) {
    const auto end = std::min(id.find('_', start), id.size());
    if (id.substr(start, end - start) == word) return true;
    start = end + 1;
  }
  return false;
}

}  // namespace

std::string_view state_class_name(StateClass state_class) {
  switch (state_class) {
    case StateClass::measurement: return "measurement";
    case StateClass::total_increasing: return "total_increasing";
    case StateClass::none: return "";
  }
  return "";
}

std::span<const SensorDeviceClass> sensor_device_classes() { return classes; }

SensorClasses sensor_classes(std::string_view home_assistant_unit, Measure measure) {
  SensorClasses result;
  switch (measure) {
    case Measure::code: return result;
    case Measure::quantity: result.state_class = StateClass::measurement; break;
    case Measure::counter: result.state_class = StateClass::total_increasing; break;
  }
  for (const auto& device_class : classes)
    if (std::ranges::find(device_class.units, home_assistant_unit) != device_class.units.end()) {
      if (allows(device_class, result.state_class)) result.device_class = device_class.name;
      break;
    }
  return result;
}

bool is_alarm_bit(std::string_view word_id, std::string_view field_id) {
  if (std::ranges::find(alarm_words, word_id) != alarm_words.end()) return true;
  return std::ranges::any_of(alarm_id_words, [&](std::string_view word) { return has_id_word(field_id, word); });
}

}  // namespace unima::mqtt
