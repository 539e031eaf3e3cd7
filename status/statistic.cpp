#include "status/statistic.hpp"

#include <chrono>

#include "platform/utc_time.hpp"

namespace unima::status {

const char* type_name(MetricType type) {
  switch (type) {
    case MetricType::counter: return "counter";
    case MetricType::gauge: return "gauge";
    case MetricType::summary: return "summary";
  }
  return "untyped";
}

std::optional<double> unix_seconds(const std::optional<std::string>& time) {
  if (!time) return std::nullopt;
  const auto parsed = platform::parse_utc_time(*time);
  if (!parsed) return std::nullopt;
  return std::chrono::duration<double>(parsed->time_since_epoch()).count();
}

}  // namespace unima::status
