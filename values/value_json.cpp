#include "values/value_json.hpp"

#include <cmath>

namespace unima::values {

std::string_view state_name(State state) {
  switch (state) {
    case State::ok: return "ok";
    case State::not_measured: return "not measured";
    case State::offline: return "off-line";
    case State::not_set: return "not set";
    case State::not_mapped: return "not mapped";
  }
  return "?";
}

std::string_view type_name(const ValueDef& def) {
  if (def.decoding == Decoding::word) return "bits";
  switch (def.type) {
    case ValueType::number: return "number";
    case ValueType::boolean: return "boolean";
    case ValueType::text: return "text";
  }
  return "?";
}

nlohmann::json reading_json(const ValueDef& def, const Value& value) {
  if (const auto* number = std::get_if<double>(&value.reading)) {
    if (def.decimals == 0) return static_cast<std::int64_t>(std::llround(*number));
    return *number;
  }
  if (const auto* flag = std::get_if<bool>(&value.reading)) return *flag;
  if (const auto* text = std::get_if<std::string>(&value.reading)) return *text;
  return nullptr;
}

nlohmann::json reading_state_json(const ValueDef& def, const Value& value) {
  nlohmann::json j = {{"value", reading_json(def, value)}, {"state", state_name(value.state)}};
  if (value.state == State::not_set) j["set"] = false;
  return j;
}

nlohmann::json value_json(const ValueDef& def, const Value& value) {
  auto j = reading_state_json(def, value);
  j["name"] = def.name;
  j["unit"] = def.unit;
  return j;
}

bool published(const Value& value) { return value.state != State::not_mapped && value.state != State::not_set; }

}  // namespace unima::values
