#include "mqtt/discovery.hpp"

#include <set>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "values/value_codec.hpp"

namespace unima::mqtt {

namespace {

using banks::BankId;
using Json = nlohmann::ordered_json;
using values::Decoding;
using values::ValueDef;

constexpr std::string_view manufacturer = "UNIMA-KS";

// What the whole bridge's configs share: the names and topics of this config.
struct Context {
  const config::MqttConfig& mqtt;
  std::string node_id;
  std::vector<DiscoveryMessage>& out;
};

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

Json common(const Context& context, std::string_view bank, std::string_view identifier, Json device) {
  return {{"name", identifier},
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

void add_values(Context& context, const values::BankValues& layout, const Json& device) {
  const auto bank = banks::bank_name(layout.bank);
  const auto state_topic = context.mqtt.topic + "/" + std::string(bank);
  std::set<std::string> seen;  // a source mapped twice is one key of the document
  for (const auto& def : layout.values) {
    if (!ever_published(def) || !seen.insert(def.name).second) continue;
    auto payload = common(context, bank, def.name, device);
    payload["state_topic"] = state_topic;
    payload["value_template"] = value_template(def);
    if (is_boolean(def)) {
      payload["payload_on"] = "True";
      payload["payload_off"] = "False";
      add(context, "binary_sensor", bank, def.name, payload);
      continue;
    }
    if (!def.unit.empty()) payload["unit_of_measurement"] = home_assistant_unit(def.unit);
    if (def.type == values::ValueType::number) payload["suggested_display_precision"] = def.decimals;
    add(context, "sensor", bank, def.name, payload);
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
    auto payload = common(context, "W", def.name, device);
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
    auto payload = common(context, "X", def.name, device);
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
  Context context{mqtt, discovery_id(mqtt.client_id), messages};
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
