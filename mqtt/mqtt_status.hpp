#pragma once
// The MQTT client's entry in the status document ("mqtt", SPEC §12, §15) and its statistics.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "status/statistic.hpp"

namespace unima::mqtt {

/// The history buffer of a broker outage (`mqtt.buffer`).
struct BufferStatus {
  std::string file;
  std::uint64_t bytes = 0;         // written and not yet acknowledged
  std::uint64_t messages = 0;      // those documents
  std::uint64_t dropped = 0;       // by a full buffer, the oldest first
  std::uint64_t history_sent = 0;  // acknowledged by the broker
  std::uint64_t syncs = 0;         // fdatasync calls
  std::uint64_t failures = 0;      // writes or reads the disk refused
};

struct MqttStatus {
  std::string broker;
  std::string client_id;
  std::string topic;
  bool connected = false;
  std::uint64_t connections = 0;
  std::uint64_t drops = 0;
  std::uint64_t published = 0;
  std::uint64_t session_takeovers = 0;
  std::uint64_t retained_commands_dropped = 0;  // set/… messages from the broker's store
  std::uint64_t response_topics_refused = 0;    // answered on set/result instead (mqtt/response_topic)
  std::uint64_t retained_configs_dropped = 0;   // config/set messages from the broker's store, cleared
  std::string since;                         // UTC: connected since, or not connected since
  std::optional<std::string> last_takeover;  // UTC; none yet: null
  std::optional<std::string> last_error;
  std::optional<BufferStatus> buffer;        // without `mqtt.buffer`: null
};

NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE_WITH_DEFAULT(BufferStatus, file, bytes, messages, dropped, history_sent, syncs, failures)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE_WITH_DEFAULT(MqttStatus, broker, client_id, topic, connected, connections, drops, published,
                                                session_takeovers, retained_commands_dropped, response_topics_refused,
                                                retained_configs_dropped, since,
                                                last_takeover, last_error, buffer)

const std::vector<status::Statistic<MqttStatus>>& mqtt_statistics();
/// The buffer's, written only when there is one.
const std::vector<status::Statistic<BufferStatus>>& buffer_statistics();

}  // namespace unima::mqtt
