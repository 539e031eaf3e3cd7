#pragma once
// The monitor's part of the status document — "modbus" (the Modbus LED, a
// status::Activity), "indicators" (the capture indicators, SPEC §8) and "monitor" (where
// the log goes, its filter, its lines written and dropped) — and its statistics. Filled by
// io/monitor_service. A library of its own beside unima_monitor: status/ reads the
// monitor's time text, so the monitor's library cannot take status/ back.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "status/statistic.hpp"

namespace unima::monitor {

/// A capture indicator: the register it watches and what it last saw there.
struct IndicatorStatus {
  std::uint64_t address = 0;            // the Modbus unit
  std::uint64_t reg = 0;                // "register"
  std::optional<std::uint64_t> value;   // none (null): nothing seen yet, nor access and time
  std::optional<std::string> access;    // "read" or "write"
  std::optional<std::string> time;      // UTC, as the monitor's lines write it
};
void to_json(nlohmann::json& j, const IndicatorStatus& s);
void from_json(const nlohmann::json& j, IndicatorStatus& s);

/// The traffic monitor's log.
struct MonitorStatus {
  std::optional<std::string> file;  // none (null): no file
  bool to_stdout = false;           // "stdout"
  std::string format;               // "text" or "json"
  std::string filter;               // the command filter, in `monitor --filter`'s words
  std::uint64_t queue = 0;          // the ring's slots
  std::uint64_t written = 0;        // lines
  std::uint64_t dropped = 0;        // lines the writer fell behind on
};
void to_json(nlohmann::json& j, const MonitorStatus& s);
void from_json(const nlohmann::json& j, MonitorStatus& s);

const std::vector<status::Statistic<MonitorStatus>>& monitor_statistics();

}  // namespace unima::monitor
