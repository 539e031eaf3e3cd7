#pragma once

#include <string>

namespace unima::daemon {

/// Logs to stderr; `level` is one of spdlog's names (trace .. off). Under systemd
/// (JOURNAL_STREAM set) the journal adds the time itself, so the lines carry none.
void setup_logging(const std::string& level);
void set_log_level(const std::string& level);

}  // namespace unima::daemon
