#include "sparkplug/edge_status.hpp"

namespace unima::sparkplug {

const std::vector<status::Statistic<EdgeStatus>>& edge_statistics() {
  using enum status::MetricType;
  using status::Samples;
  static const std::vector<status::Statistic<EdgeStatus>> all{
      {"sparkplug_connected", gauge, "1 while the Sparkplug B edge node is connected to its broker.",
       [](const EdgeStatus& s, Samples& out) { out.add(s.connected); }},
      {"sparkplug_born", gauge, "1 while the edge node's NBIRTH stands (connected, and its primary host online).",
       [](const EdgeStatus& s, Samples& out) { out.add(s.born); }},
      {"sparkplug_bd_seq", gauge, "The bdSeq of the edge node's present MQTT connection (0-255).",
       [](const EdgeStatus& s, Samples& out) { out.add(s.bdSeq); }},
      {"sparkplug_seq", gauge, "The seq the edge node's next message carries (0-255).",
       [](const EdgeStatus& s, Samples& out) { out.add(s.seq); }},
      {"sparkplug_state_since_timestamp_seconds", gauge,
       "When the edge node's present state (sparkplug_connected 1 or 0) began, in Unix seconds.",
       [](const EdgeStatus& s, Samples& out) { out.add(status::unix_seconds(s.since)); }},
      {"sparkplug_connections_total", counter, "Connections made to the Sparkplug broker.",
       [](const EdgeStatus& s, Samples& out) { out.add(s.connections); }},
      {"sparkplug_births_total", counter, "NBIRTH and DBIRTH messages published.",
       [](const EdgeStatus& s, Samples& out) { out.add(s.births); }},
      {"sparkplug_data_total", counter, "DDATA messages published.", [](const EdgeStatus& s, Samples& out) { out.add(s.data); }},
      {"sparkplug_device_deaths_total", counter, "DDEATH messages published.",
       [](const EdgeStatus& s, Samples& out) { out.add(s.deaths); }},
      {"sparkplug_rebirths_coalesced_total", counter,
       "NCMD rebirth requests carried out together with another: at most one rebirth per 5 s.",
       [](const EdgeStatus& s, Samples& out) { out.add(s.rebirths_coalesced); }},
      {"sparkplug_commands_total", counter,
       "NCMD/DCMD metrics taken (a rebirth, a write) or refused, and command messages malformed or retained (dropped).",
       [](const EdgeStatus& s, Samples& out) {
         out.add(s.commands.taken, {{"outcome", "taken"}})
             .add(s.commands.refused, {{"outcome", "refused"}})
             .add(s.commands.malformed, {{"outcome", "malformed"}})
             .add(s.commands.retained, {{"outcome", "retained"}});
       }},
  };
  return all;
}

}  // namespace unima::sparkplug
