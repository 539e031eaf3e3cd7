#pragma once
// The Sparkplug B edge node's entry in the status document ("sparkplug", SPEC §16) and
// its statistics.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "status/statistic.hpp"

namespace unima::sparkplug {

/// NCMD/DCMD metrics taken (a rebirth, a write) or refused, and command messages malformed.
struct CommandCounts {
  std::uint64_t taken = 0;
  std::uint64_t refused = 0;
  std::uint64_t malformed = 0;
  std::uint64_t retained = 0;  // NCMD/DCMD from the broker's store, dropped (Sparkplug 3.0: never retained)
};

/// `sparkplug.primary_host` and what its last STATE said ("online", "offline", "unknown").
struct PrimaryHostStatus {
  std::string name;
  std::string state;
};

struct EdgeStatus {
  std::string broker;
  std::string client_id;
  std::string group_id;
  std::string edge_node_id;
  bool connected = false;
  bool born = false;  // the NBIRTH stands: connected, and the primary host online
  std::uint64_t connections = 0;
  std::uint64_t drops = 0;
  std::uint64_t published = 0;
  std::uint64_t births = 0;  // NBIRTH and DBIRTH
  std::uint64_t data = 0;    // DDATA
  std::uint64_t deaths = 0;  // DDEATH
  CommandCounts commands;
  std::uint64_t rebirths_coalesced = 0;  // NCMD rebirths carried out with another (sparkplug/rebirth_pacing)
  std::optional<std::uint64_t> bdSeq;  // NOLINT(readability-identifier-naming): Sparkplug's word, the document's key
  std::uint64_t seq = 0;               // the next message's
  std::string since;                   // UTC: connected since, or not connected since
  std::optional<PrimaryHostStatus> primary_host;
  std::optional<std::string> last_error;
};

NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE_WITH_DEFAULT(CommandCounts, taken, refused, malformed, retained)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE_WITH_DEFAULT(PrimaryHostStatus, name, state)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE_WITH_DEFAULT(EdgeStatus, broker, client_id, group_id, edge_node_id, connected, born,
                                                connections, drops, published, births, data, deaths, commands, rebirths_coalesced, bdSeq, seq,
                                                since, primary_host, last_error)

const std::vector<status::Statistic<EdgeStatus>>& edge_statistics();

}  // namespace unima::sparkplug
