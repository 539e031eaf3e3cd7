#pragma once

#include <string>

namespace unima::platform {

/// Logs to stderr; `level` is one of spdlog's names (trace .. off). When stderr is the
/// journal (systemd's JOURNAL_STREAM names it), each line is "<priority>message": journald
/// adds the time itself and files the line under that syslog priority.
void setup_logging(const std::string& level);
void set_log_level(const std::string& level);

}  // namespace unima::platform
