#pragma once
// The monitor's settings (SPEC §5, seed 004 §8; YAML section `monitor`, read by config/):
// where the log goes and in which format, the command filter, the capture indicators.

#include <cstdint>
#include <string>
#include <vector>

#include "monitor/capture_indicators.hpp"
#include "monitor/command_filter.hpp"

namespace unima::monitor {

enum class MonitorFormat : std::uint8_t { text, json };

/// Off unless a file or stdout is set.
struct MonitorConfig {
  std::string file;             // size-rotated: file, file.1 .. file.<max_files>
  bool to_stdout = false;       // key "stdout"
  MonitorFormat format = MonitorFormat::text;
  std::uint64_t max_size = 10ull << 20;
  unsigned max_files = 5;
  unsigned queue = 4096;        // transactions waiting for the writer; more are dropped and counted
  CommandFilter filter;
  std::vector<IndicatorSpec> indicators;  // at most CaptureIndicators::max_indicators
  bool enabled() const { return !file.empty() || to_stdout; }
};

}  // namespace unima::monitor
