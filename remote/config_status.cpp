#include "remote/config_status.hpp"

#include "status/json_optional.hpp"

namespace unima::remote {

NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE_WITH_DEFAULT(LastChange, id, result, reason, source, by, at)

const std::vector<status::Statistic<ConfigStatus>>& config_statistics() {
  using enum status::MetricType;
  using status::Samples;
  static const std::vector<status::Statistic<ConfigStatus>> all{
      {"config_info", gauge,
       "The config in force: where it came from (file: the operator's; cli, mqtt, http: sent from afar) and its sha256.",
       [](const ConfigStatus& s, Samples& out) { out.add(1, {{"source", s.source}, {"sha256", s.sha256}}); }},
      {"config_applied_timestamp_seconds", gauge,
       "When the config in force was applied from afar, in Unix seconds (the operator's file: absent).",
       [](const ConfigStatus& s, Samples& out) { out.add(status::unix_seconds(s.applied_at)); }},
      {"config_changes_total", counter, "Configs sent from afar since the start, by how each ended.",
       [](const ConfigStatus& s, Samples& out) {
         out.add(s.changes_applied, {{"result", "applied"}})
             .add(s.changes_refused, {{"result", "refused"}})
             .add(s.changes_rolled_back, {{"result", "rolled_back"}})
             .add(s.changes_busy, {{"result", "busy"}});
       }},
      {"config_last_change_timestamp_seconds", gauge,
       "When the last config sent from afar was answered, in Unix seconds, labelled with its result (none yet: absent).",
       [](const ConfigStatus& s, Samples& out) {
         if (s.last) out.add(status::unix_seconds(s.last->at), {{"result", s.last->result}});
       }},
  };
  return all;
}

void to_json(nlohmann::json& j, const ConfigStatus& s) {
  j = {{"source", s.source},
       {"file", s.file},
       {"sha256", s.sha256},
       {"number", s.number},
       {"by", s.by},
       {"applied_at", s.applied_at},
       {"last", s.last},
       {"changes", {{"applied", s.changes_applied},
                    {"refused", s.changes_refused},
                    {"rolled_back", s.changes_rolled_back},
                    {"busy", s.changes_busy}}}};
}

void from_json(const nlohmann::json& j, ConfigStatus& s) {
  s = {};
  s.source = j.value("source", std::string("file"));
  s.file = j.value("file", std::string{});
  s.sha256 = j.value("sha256", std::string{});
  if (j.contains("number")) s.number = j["number"].get<std::optional<unsigned>>();
  if (j.contains("by")) s.by = j["by"].get<std::optional<std::string>>();
  if (j.contains("applied_at")) s.applied_at = j["applied_at"].get<std::optional<std::string>>();
  if (j.contains("last")) s.last = j["last"].get<std::optional<LastChange>>();
  if (const auto changes = j.find("changes"); changes != j.end() && changes->is_object()) {
    s.changes_applied = changes->value("applied", std::uint64_t{0});
    s.changes_refused = changes->value("refused", std::uint64_t{0});
    s.changes_rolled_back = changes->value("rolled_back", std::uint64_t{0});
    s.changes_busy = changes->value("busy", std::uint64_t{0});
  }
}

}  // namespace unima::remote
