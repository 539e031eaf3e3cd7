#pragma once
// The state file's entry in the status document ("state") and its statistics.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "status/statistic.hpp"

namespace unima::state {

struct StateStatus {
  std::optional<std::string> file;  // none: `state.file: none`, and no counters either
  std::uint64_t records = 0;        // writes recorded
  std::uint64_t syncs = 0;          // fdatasync calls
  std::uint64_t failures = 0;       // writes that failed
};
void to_json(nlohmann::json& j, const StateStatus& s);
void from_json(const nlohmann::json& j, StateStatus& s);

const std::vector<status::Statistic<StateStatus>>& state_statistics();

}  // namespace unima::state
