#include "mqtt/mqtt_status.hpp"

namespace unima::mqtt {

const std::vector<status::Statistic<MqttStatus>>& mqtt_statistics() {
  using enum status::MetricType;
  using status::Samples;
  static const std::vector<status::Statistic<MqttStatus>> all{
      {"mqtt_connected", gauge, "1 while the MQTT client is connected to its broker.",
       [](const MqttStatus& s, Samples& out) { out.add(s.connected); }},
      {"mqtt_connections_total", counter, "Connections made to the MQTT broker.",
       [](const MqttStatus& s, Samples& out) { out.add(s.connections); }},
      {"mqtt_drops_total", counter, "Connections to the MQTT broker that dropped.",
       [](const MqttStatus& s, Samples& out) { out.add(s.drops); }},
      {"mqtt_published_total", counter, "MQTT messages handed to the broker's connection.",
       [](const MqttStatus& s, Samples& out) { out.add(s.published); }},
      {"mqtt_session_takeovers_total", counter,
       "Times the MQTT broker gave the bridge's session to another client with its client id.",
       [](const MqttStatus& s, Samples& out) { out.add(s.session_takeovers); }},
      {"mqtt_retained_commands_dropped_total", counter,
       "Retained commands (set/...) the broker delivered from its store, dropped: a command is carried out only when published.",
       [](const MqttStatus& s, Samples& out) { out.add(s.retained_commands_dropped); }},
      {"mqtt_response_topics_refused_total", counter,
       "MQTT 5 Response Topics the bridge would not answer on (not in mqtt.response_topics, or its own topics): answered on set/result.",
       [](const MqttStatus& s, Samples& out) { out.add(s.response_topics_refused); }},
      {"mqtt_retained_configs_dropped_total", counter,
       "Retained configs (config/set) the broker delivered from its store: never applied, cleared on the broker.",
       [](const MqttStatus& s, Samples& out) { out.add(s.retained_configs_dropped); }},
      {"mqtt_state_since_timestamp_seconds", gauge,
       "When the MQTT client's present state (mqtt_connected 1 or 0) began, in Unix seconds.",
       [](const MqttStatus& s, Samples& out) { out.add(status::unix_seconds(s.since)); }},
      {"mqtt_last_session_takeover_timestamp_seconds", gauge,
       "When the MQTT broker last gave the bridge's session to another client, in Unix seconds (none yet: absent).",
       [](const MqttStatus& s, Samples& out) { out.add(status::unix_seconds(s.last_takeover)); }},
  };
  return all;
}

const std::vector<status::Statistic<BufferStatus>>& buffer_statistics() {
  using enum status::MetricType;
  using status::Samples;
  static const std::vector<status::Statistic<BufferStatus>> all{
      {"mqtt_buffer_bytes", gauge, "Bytes of history in the MQTT buffer not yet acknowledged by the broker.",
       [](const BufferStatus& b, Samples& out) { out.add(b.bytes); }},
      {"mqtt_buffer_messages", gauge, "Documents in the MQTT buffer not yet acknowledged by the broker.",
       [](const BufferStatus& b, Samples& out) { out.add(b.messages); }},
      {"mqtt_buffer_dropped_total", counter, "Documents the full MQTT buffer dropped (the oldest first).",
       [](const BufferStatus& b, Samples& out) { out.add(b.dropped); }},
      {"mqtt_buffer_history_sent_total", counter, "History messages the broker acknowledged.",
       [](const BufferStatus& b, Samples& out) { out.add(b.history_sent); }},
      {"mqtt_buffer_syncs_total", counter, "fdatasync calls of the MQTT buffer (at most one a second).",
       [](const BufferStatus& b, Samples& out) { out.add(b.syncs); }},
      {"mqtt_buffer_failures_total", counter, "MQTT buffer writes or reads the disk refused.",
       [](const BufferStatus& b, Samples& out) { out.add(b.failures); }},
  };
  return all;
}

}  // namespace unima::mqtt
