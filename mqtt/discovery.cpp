#include "mqtt/discovery.hpp"

#include <map>
#include <set>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "mqtt/home_assistant_classes.hpp"
#include "values/value_codec.hpp"

namespace unima::mqtt {

namespace {

using banks::BankId;
using Json = nlohmann::ordered_json;
using values::Decoding;
using values::ValueDef;

constexpr std::string_view manufacturer = "UNIMA-KS";

// What the whole bridge's configs share: the names and topics of this config, and the
// tables its values are read from.
struct Context {
  const config::MqttConfig& mqtt;
  banks::BankShapes shapes;
  std::string node_id;
  std::vector<DiscoveryMessage>& out;
};

// The table register a value reads: its own for a D_N value, its source's for an entry of
// A or B; nullptr where there is no table (W, X).
const banks::RegisterDef* table_register(const Context& context, BankId bank, const ValueDef& def) {
  const auto table_bank = def.source ? def.source->bank : bank;
  const auto offset = def.source ? def.source->offset : def.offsets.front();
  const auto* table = context.shapes[banks::index_of(table_bank)].table;
  return table && offset < table->length() ? &table->registers[offset] : nullptr;
}

// What a number is to Home Assistant's statistics, from the register it reads: the tables
// keep their running totals (operating hours, energy generated) in 32-bit pairs, and
// nothing else; bit words and fields of several bits are states, not quantities.
Measure measure_of(const ValueDef& def, const banks::RegisterDef* reg) {
  switch (def.decoding) {
    case Decoding::pair32: return Measure::counter;
    case Decoding::analog:
    case Decoding::byte_field: return Measure::quantity;
    case Decoding::word:
    case Decoding::bit_field:
    case Decoding::ascii:
    case Decoding::mapped_bit: return Measure::code;
    case Decoding::mapped: break;
  }
  if (!reg) return Measure::quantity;  // W: tenths of a quantity
  switch (reg->kind) {
    case banks::RegisterKind::analog: return Measure::quantity;
    case banks::RegisterKind::u32_low:
    case banks::RegisterKind::u32_high: return Measure::counter;  // a half of a running total
    default: return Measure::code;
  }
}

// Whether the bit a value reads is an alarm (mqtt/home_assistant_classes): a D_N's own
// named bit, or the source of a B entry.
bool is_alarm(const ValueDef& def, const banks::RegisterDef* reg) {
  if (!reg) return false;
  const unsigned bit = def.source && def.source->bit ? *def.source->bit : def.first_bit;
  for (const auto& field : reg->fields)
    if (field.first_bit == bit && field.last_bit == bit) return is_alarm_bit(reg->id, field.id);
  return false;
}

// What a person reads in Home Assistant: the table's label (Czech, as the seed prints it);
// the document's key where the table has none (B, W, X, a_00); a label that several values
// of the device share, and an entry of A, which shows another device's value, also say
// which value they are ("Binární vstupy (control_inputs)", "Teplota oleje (D1.oil_temperature)").
std::string entity_name(const ValueDef& def, const std::map<std::string, unsigned>& label_uses) {
  if (def.label.empty()) return def.name;
  const auto uses = label_uses.find(def.label);
  if (def.source || (uses != label_uses.end() && uses->second > 1)) return def.label + " (" + def.name + ")";
  return def.label;
}

// Home Assistant's slug of a name (its util.slugify: lower case, every run of other
// characters one '_', none at either end), for ASCII text.
std::string slug(std::string_view text) {
  std::string out;
  for (const char c : text) {
    const bool keep = (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9');
    if (keep) out += c;
    else if (c >= 'A' && c <= 'Z') out += static_cast<char>(c - 'A' + 'a');
    else if (!out.empty() && out.back() != '_') out += '_';
  }
  while (!out.empty() && out.back() == '_') out.pop_back();
  return out;
}

// Bracketed always: `value_json.values` would find the dict's method before the key, and a
// dotted key ("knock_rank_1.level", "D1.oil_temperature") is one key, not a path.
std::string value_template(std::string_view key) {
  std::string quoted;
  for (const char c : key) {
    if (c == '\'' || c == '\\') quoted += '\\';
    quoted += c;
  }
  return "{{ value_json['" + quoted + "'] }}";
}

// A mapped entry whose source is W or X is absent from the document until a master writes
// it (SPEC §17): `default(none)` makes the missing key unknown like a null, not an error.
std::string value_template(const ValueDef& def) {
  auto text = value_template(def.name);
  if (def.source && banks::is_write_bank(def.source->bank)) text.insert(text.size() - 3, " | default(none)");
  return text;
}

Json bridge_device(const config::MqttConfig& mqtt) {
  return {{"identifiers", Json::array({mqtt.client_id})}, {"name", mqtt.client_id}, {"model", "unima-bridge"}};
}

Json station_device(const config::Config& config, BankId bank) {
  const auto& mqtt = *config.mqtt;
  const auto& device = config.devices[banks::bank_number(bank) - 1];
  const auto name = std::string(banks::bank_name(bank));
  return {{"identifiers", Json::array({mqtt.client_id + "_" + name})},
          {"name", mqtt.client_id + " " + name},
          {"model", device && device->table ? device->table->id : std::string()},
          {"manufacturer", manufacturer},
          {"via_device", mqtt.client_id}};
}

// `name` is what a person reads; the entity id stays the one Home Assistant made when the
// name was the document's key, `<component>.<device name> <key>` as its slug
// (`sensor.site_17_d1_engine_speed`): automations and dashboards written against it keep
// working (`default_entity_id`; a Home Assistant older than that key ignores it, and any
// Home Assistant keeps the entity ids it has already given, by unique_id).
Json common(const Context& context, std::string_view component, std::string_view bank, std::string_view identifier,
            std::string name, Json device) {
  const auto default_entity_id = fmt::format("{}.{}", component, slug(device["name"].get<std::string>() + " " + std::string(identifier)));
  return {{"name", std::move(name)},
          {"default_entity_id", default_entity_id},
          {"unique_id", context.mqtt.client_id + "_" + std::string(bank) + "_" + std::string(identifier)},
          {"availability_topic", context.mqtt.topic + "/status"},
          {"payload_available", "online"},
          {"payload_not_available", "offline"},
          {"device", std::move(device)},
          {"origin", {{"name", "unima-bridge"}}}};
}

void add(Context& context, std::string_view component, std::string_view bank, std::string_view identifier, const Json& payload) {
  const auto object_id = discovery_id(std::string(bank) + "_" + std::string(identifier));
  context.out.push_back({fmt::format("{}/{}/{}/{}/config", context.mqtt.discovery->prefix, component, context.node_id, object_id),
                         payload.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace)});
}

bool is_boolean(const ValueDef& def) { return def.type == values::ValueType::boolean; }

// What the bank documents publish (mqtt/bank_documents.hpp) that a config can know of:
// an unmapped entry of A, or B's stand-in when nothing is mapped, never is.
bool ever_published(const ValueDef& def) {
  return !((def.decoding == Decoding::mapped || def.decoding == Decoding::mapped_bit) && !def.source);
}

// A D_N's named bit that is no alarm is a detail a technician looks up, not a state a
// person watches: diagnostic, and disabled until enabled (a CHP unit has some 150). An
// alarm stays in sight as a problem; B's entries, which the integrator mapped, do too.
void add_bit_classes(Json& payload, BankId bank, bool alarm) {
  if (alarm) {
    payload["device_class"] = "problem";
  } else if (banks::is_device_bank(bank)) {
    payload["entity_category"] = "diagnostic";
    payload["enabled_by_default"] = false;
  }
}

void add_sensor_classes(Json& payload, const ValueDef& def, const banks::RegisterDef* reg) {
  const auto unit = home_assistant_unit(def.unit);
  if (!unit.empty()) payload["unit_of_measurement"] = unit;
  if (def.type != values::ValueType::number) return;
  const auto classes = sensor_classes(unit, measure_of(def, reg));
  if (!classes.device_class.empty()) payload["device_class"] = classes.device_class;
  if (classes.state_class != StateClass::none) payload["state_class"] = state_class_name(classes.state_class);
  payload["suggested_display_precision"] = values::display_decimals(def);
}

void add_values(Context& context, const values::BankValues& layout, const Json& device) {
  const auto bank = banks::bank_name(layout.bank);
  const auto state_topic = context.mqtt.topic + "/" + std::string(bank);
  std::map<std::string, unsigned> label_uses;
  for (const auto& def : layout.values)
    if (ever_published(def)) ++label_uses[def.label];
  std::set<std::string> seen;  // a source mapped twice is one key of the document
  for (const auto& def : layout.values) {
    if (!ever_published(def) || !seen.insert(def.name).second) continue;
    const auto* reg = table_register(context, layout.bank, def);
    const auto component = is_boolean(def) ? "binary_sensor" : "sensor";
    auto payload = common(context, component, bank, def.name, entity_name(def, label_uses), device);
    payload["state_topic"] = state_topic;
    payload["value_template"] = value_template(def);
    if (is_boolean(def)) {
      payload["payload_on"] = "True";
      payload["payload_off"] = "False";
      add_bit_classes(payload, layout.bank, is_alarm(def, reg));
    } else {
      add_sensor_classes(payload, def, reg);
    }
    add(context, component, bank, def.name, payload);
  }
}

// Home Assistant sets a W value in its unit; the command topic takes the register (SPEC
// §12: a whole number). The template is the way back of values/value_codec in Jinja: the
// value ÷ the step when that is whole (within the codec's millionth of a step), else the
// value as it is, which set/W refuses as no whole number — a finer fraction is refused,
// not rounded. The range and step are the codec's, so Home Assistant refuses the rest.
std::string register_template(double step) {
  return fmt::format("{{% set raw = value / {} %}}{{{{ (raw | round | int) if (raw - raw | round) | abs < 0.000001 else value }}}}",
                     step);
}

void add_setpoints(Context& context, const values::BankValues& layout, const Json& device) {
  for (const auto& def : layout.values) {
    const auto range = values::accepted(def);
    if (!range) continue;
    auto payload = common(context, "number", "W", def.name, def.name, device);
    payload["command_topic"] = fmt::format("{}/set/W/{}", context.mqtt.topic, def.offsets.front());
    payload["command_template"] = register_template(range->step);
    payload["min"] = range->min;
    payload["max"] = range->max;
    payload["step"] = range->step;
    payload["mode"] = "box";
    payload["qos"] = 1;
    payload["retain"] = false;  // a retained command would be written again at every reconnect
    add(context, "number", "W", def.name, payload);
  }
}

// A switch per bit of X, as the value model names them (values/value_layout.cpp): set/X
// takes the bit's number (SPEC §12).
void add_switches(Context& context, const values::BankValues& layout, const Json& device) {
  for (const auto& def : layout.values) {
    if (!is_boolean(def)) continue;
    auto payload = common(context, "switch", "X", def.name, def.name, device);
    payload["command_topic"] = fmt::format("{}/set/X/{}", context.mqtt.topic, def.first_bit);
    payload["payload_on"] = "1";
    payload["payload_off"] = "0";
    payload["qos"] = 1;
    payload["retain"] = false;
    add(context, "switch", "X", def.name, payload);
  }
}

}  // namespace

std::vector<DiscoveryMessage> discovery_messages(const config::Config& config, const values::ValueModel& model) {
  std::vector<DiscoveryMessage> messages;
  if (!config.mqtt || !config.mqtt->discovery) return messages;
  const auto& mqtt = *config.mqtt;
  Context context{mqtt, config::bank_shapes(config), discovery_id(mqtt.client_id), messages};
  const auto bridge = bridge_device(mqtt);
  for (const auto& layout : model.banks())
    if (banks::is_device_bank(layout.bank)) add_values(context, layout, station_device(config, layout.bank));
  for (const auto bank : {BankId::A, BankId::B})
    if (const auto* layout = model.bank(bank)) add_values(context, *layout, bridge);
  if (!mqtt.commands) return messages;
  if (const auto* w = model.bank(BankId::W)) add_setpoints(context, *w, bridge);
  if (const auto* x = model.bank(BankId::X)) add_switches(context, *x, bridge);
  return messages;
}

std::vector<std::string> withdrawn_topics(std::span<const DiscoveryMessage> before, std::span<const DiscoveryMessage> after) {
  std::set<std::string_view> served;
  for (const auto& message : after) served.insert(message.topic);
  std::vector<std::string> withdrawn;
  for (const auto& message : before)
    if (!served.contains(message.topic)) withdrawn.push_back(message.topic);
  return withdrawn;
}

std::string home_assistant_status_topic(const config::Config& config) {
  if (!config.mqtt || !config.mqtt->discovery) return {};
  return config.mqtt->discovery->prefix + "/status";
}

std::string discovery_id(std::string_view text) {
  std::string id(text);
  for (auto& c : id)
    if (!((c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '-')) c = '_';
  return id;
}

std::string_view home_assistant_unit(std::string_view table_unit) {
  if (table_unit == "min-1") return "rpm";
  if (table_unit == "kVAr") return "kvar";
  return table_unit;
}

}  // namespace unima::mqtt
