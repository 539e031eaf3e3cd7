#pragma once

#include <memory>
#include <string>

#include <spdlog/formatter.h>

namespace unima::platform {

/// Logs to stderr; `level` is one of spdlog's names (trace .. off). When stderr is the
/// journal (systemd's JOURNAL_STREAM names it), each line is "<priority>message": journald
/// adds the time itself and files the line under that syslog priority.
void setup_logging(const std::string& level);
/// The format of each line: the time, level and message, or for the journal the priority
/// prefix and the message; control characters in the message escaped (platform/log_text).
std::unique_ptr<spdlog::formatter> log_formatter(bool to_journal);
void set_log_level(const std::string& level);

}  // namespace unima::platform
