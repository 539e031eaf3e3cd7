#include "state/state_status.hpp"

namespace unima::state {

void to_json(nlohmann::json& j, const StateStatus& s) {
  j = {{"file", s.file}};
  if (!s.file) return;
  j["records"] = s.records;
  j["syncs"] = s.syncs;
  j["failures"] = s.failures;
}

void from_json(const nlohmann::json& j, StateStatus& s) {
  s.file = j.value("file", std::optional<std::string>{});
  s.records = j.value("records", std::uint64_t{0});
  s.syncs = j.value("syncs", std::uint64_t{0});
  s.failures = j.value("failures", std::uint64_t{0});
}

namespace {
// Without a file nothing is counted: no sample rather than a 0 that was never counted.
std::optional<std::uint64_t> counted(const StateStatus& s, std::uint64_t value) {
  return s.file ? std::optional(value) : std::nullopt;
}
}  // namespace

const std::vector<status::Statistic<StateStatus>>& state_statistics() {
  using enum status::MetricType;
  static const std::vector<status::Statistic<StateStatus>> all{
      {"state_records_total", counter, "Writes recorded in the state file.",
       [](const StateStatus& s, status::Samples& out) { out.add(counted(s, s.records)); }},
      {"state_syncs_total", counter, "fdatasync calls of the state file.",
       [](const StateStatus& s, status::Samples& out) { out.add(counted(s, s.syncs)); }},
      {"state_failures_total", counter, "State file writes that failed.",
       [](const StateStatus& s, status::Samples& out) { out.add(counted(s, s.failures)); }},
  };
  return all;
}

}  // namespace unima::state
