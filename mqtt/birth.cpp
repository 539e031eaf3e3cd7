#include "mqtt/birth.hpp"

#include <nlohmann/json.hpp>

#include "platform/utc_time.hpp"

namespace unima::mqtt {

namespace {

template <typename T>
nlohmann::ordered_json or_null(const std::optional<T>& value) {
  return value ? nlohmann::ordered_json(*value) : nlohmann::ordered_json(nullptr);
}

}  // namespace

std::string birth_document(const BirthFacts& facts) {
  std::string started;
  platform::append_utc_time(started, facts.started);
  nlohmann::ordered_json document;
  document["version"] = facts.version;
  document["config_sha256"] = facts.config_sha256;
  document["started"] = started;
  document["hostname"] = facts.hostname;
  document["machine_id"] = facts.machine_id.empty() ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(facts.machine_id);
  document["clock_synced"] = facts.clock_synced;
  const auto& config = facts.config;
  document["config"] = {{"source", config.source},           {"number", or_null(config.number)},
                        {"by", or_null(config.by)},           {"applied_at", or_null(config.applied_at)},
                        {"last_result", or_null(config.last_result)}, {"last_reason", or_null(config.last_reason)}};
  return document.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

}  // namespace unima::mqtt
