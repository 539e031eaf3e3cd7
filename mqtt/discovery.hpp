#pragma once
// Home Assistant's MQTT discovery (SPEC §15, `mqtt.discovery`): one retained config per
// value the bank documents publish of D1..D4, A and B, and — with `commands: true` — one
// per W register and X bit, so that Home Assistant shows the bridge's values without a
// line of its YAML. Pure: from the config and its value model to (topic, payload) pairs;
// io::MqttService publishes them.
//
// Every key is Home Assistant's documented discovery schema:
// - the topic `<discovery prefix>/<component>/<node id>/<object id>/config`, node and
//   object ids of [a-zA-Z0-9_-] only: home-assistant.io/integrations/mqtt/ "Discovery topic";
// - `name` (the table's label), `default_entity_id` (the entity id the document's key gave),
//   `unique_id`, `availability_topic` with `payload_available` / `payload_not_available`,
//   `device` (`identifiers`, `name`, `model`, `manufacturer`, `via_device`) and `origin`
//   (`name`): the same page, "Discovery payload", and the "Configuration Variables" of each
//   component below;
// - sensor (home-assistant.io/integrations/sensor.mqtt/): `state_topic`, `value_template`,
//   `unit_of_measurement`, `device_class`, `state_class` (mqtt/home_assistant_classes),
//   `suggested_display_precision` (the scale's step, values::display_decimals). A JSON null
//   rendered by a value_template is the text `None`, which sets a sensor that expects a
//   number (one with a unit or a display precision) to unknown — so every number has a
//   precision;
// - binary_sensor (home-assistant.io/integrations/binary_sensor.mqtt/): `state_topic`,
//   `value_template`, `payload_on`, `payload_off`; the state follows a payload "matching
//   payload_on, payload_off or None" (None: unknown). The template renders a JSON boolean
//   as Jinja does, `True` or `False`, so those are payload_on and payload_off (zigbee2mqtt
//   configures its boolean JSON states the same way). An alarm is `device_class: problem`;
//   a D_N's other bits `entity_category: diagnostic`, `enabled_by_default: false`;
// - number (home-assistant.io/integrations/number.mqtt/): `command_topic`,
//   `command_template`, `min`, `max`, `step`, `mode`, `qos`, `retain`; without a
//   state_topic it is optimistic (shows what it last sent): W is not published;
// - switch (home-assistant.io/integrations/switch.mqtt/): `command_topic`, `payload_on`,
//   `payload_off`, `qos`, `retain`; optimistic for the same reason (X is not published).

#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "config/config.hpp"
#include "values/value_model.hpp"

namespace unima::mqtt {

struct DiscoveryMessage {
  std::string topic;    // <discovery prefix>/<component>/<node id>/<object id>/config
  std::string payload;  // the config, a JSON object; published retained
};

/// Every discovery config of `config` (its client id, prefixes, commands) and `model`:
/// D_N values in their device's order, then A, B, W, X; none without mqtt.discovery.
std::vector<DiscoveryMessage> discovery_messages(const config::Config& config, const values::ValueModel& model);

/// The topics of `before` that `after` does not serve: each is cleared with an empty
/// retained payload, which makes Home Assistant remove the entity.
std::vector<std::string> withdrawn_topics(std::span<const DiscoveryMessage> before, std::span<const DiscoveryMessage> after);

/// Where Home Assistant says `online` when it starts (its birth message): the configs are
/// published again then. Empty without mqtt.discovery.
std::string home_assistant_status_topic(const config::Config& config);

/// `text` with every character outside [a-zA-Z0-9_-] replaced by '_': a discovery topic's
/// node or object id.
std::string discovery_id(std::string_view text);

/// The unit Home Assistant writes for a device table's unit: "rpm" for "min-1", "kvar"
/// for "kVAr"; the others (°C, %, kW, kWh, V, mV, A, h, s, kPa, bar, mm, °, Ω) as they are.
std::string_view home_assistant_unit(std::string_view table_unit);

}  // namespace unima::mqtt
