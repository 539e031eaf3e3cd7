#pragma once
// A sample of a Prometheus exposition (/metrics), read as a scraper reads it.

#include <optional>
#include <sstream>
#include <string>

namespace unima::test_support {

/// The value of `series` (its name and labels as written, e.g.
/// `unima_bridge_modbus_transactions_total{port="tcp",state="Err02"}`) in `metrics`.
inline std::optional<double> prometheus_sample(const std::string& metrics, const std::string& series) {
  std::istringstream lines(metrics);
  for (std::string line; std::getline(lines, line);)
    if (line.starts_with(series + " ")) return std::stod(line.substr(series.size() + 1));
  return std::nullopt;
}

}  // namespace unima::test_support
