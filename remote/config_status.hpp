#pragma once
// The config in force as the status document shows it (SPEC §19, key "config_in_force"):
// where it came from, what it is, and how the last change sent from afar ended — for
// `unima-bridge status`, /api/status, /metrics, the birth and the page alike.

#include <cstdint>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "status/statistic.hpp"

namespace unima::remote {

/// The last change's answer (change_answer.hpp), and when it was given.
struct LastChange {
  std::string id;
  std::string result;  // applied, refused, rolled_back, busy
  std::string reason;
  std::string source;
  std::string by;
  std::string at;  // UTC
  bool operator==(const LastChange&) const = default;
};

struct ConfigStatus {
  std::string source = "file";  // file (the operator's), mqtt, http, cli
  std::string file;             // where its text is: the operator's file, or the kept copy
  std::string sha256;           // of that text
  std::optional<unsigned> number;         // the kept copy's number; a file: null
  std::optional<std::string> by;          // who sent it; a file: null
  std::optional<std::string> applied_at;  // UTC; a file: null
  std::optional<LastChange> last;         // no change since the start: null
  std::uint64_t changes_applied = 0;      // since the start, by result
  std::uint64_t changes_refused = 0;
  std::uint64_t changes_rolled_back = 0;
  std::uint64_t changes_busy = 0;
  bool operator==(const ConfigStatus&) const = default;
};

/// /metrics' families of the config in force (metrics/prometheus lists them).
const std::vector<status::Statistic<ConfigStatus>>& config_statistics();

void to_json(nlohmann::json& j, const LastChange& s);
void from_json(const nlohmann::json& j, LastChange& s);
void to_json(nlohmann::json& j, const ConfigStatus& s);
void from_json(const nlohmann::json& j, ConfigStatus& s);

}  // namespace unima::remote
