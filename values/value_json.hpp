#pragma once
// The values as JSON, one way for every consumer (SPEC §17): a number in its unit (whole
// when the scale has no decimals), a boolean, a string, or null; the state in words.

#include <string_view>

#include <nlohmann/json.hpp>

#include "values/value_model.hpp"

namespace unima::values {

/// "ok", "not measured", "off-line", "not set", "not mapped": what the page shows.
std::string_view state_name(State state);

/// "number", "boolean", "text", or "bits" for a bit word as a whole (its named bits are
/// booleans and numbers of their own): how a reading is meant to be read.
std::string_view type_name(const ValueDef& def);

/// The reading alone: what an MQTT bank document holds under the value's name.
nlohmann::json reading_json(const ValueDef& def, const Value& value);

/// {"value", "state"}, and "set": false for a W or X no master wrote: what changes of a
/// value on the page's live stream (which has the name and unit from /api/registers).
nlohmann::json reading_state_json(const ValueDef& def, const Value& value);

/// The same with "name" and "unit": what /api/registers shows.
nlohmann::json value_json(const ValueDef& def, const Value& value);

/// Whether MQTT publishes it: not an unmapped entry, not a setpoint never written.
bool published(const Value& value);

}  // namespace unima::values
