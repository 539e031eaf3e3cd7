#pragma once
// UTC time as text, the one form every output of the bridge writes a moment in: the
// monitor's lines, MQTT's documents and births, the status document, Sparkplug's and
// the master's "since". Pure: no clock, no I/O.
//
//   "2026-11-22T14:41:23.123456Z" (ISO 8601, microseconds, always 27 characters)

#include <chrono>
#include <optional>
#include <string>
#include <string_view>

namespace unima::platform {

inline constexpr std::size_t utc_time_size = 27;

/// Writes the 27 characters at `out` and returns the end. The date and clock of the last
/// second written are kept per thread: a writer stamps many lines a second, and they are
/// the costly part.
char* write_utc_time(char* out, std::chrono::system_clock::time_point time);

void append_utc_time(std::string& out, std::chrono::system_clock::time_point time);
std::string utc_time_text(std::chrono::system_clock::time_point time);

/// Exactly the form above; nullopt for anything else or a date that does not exist.
std::optional<std::chrono::system_clock::time_point> parse_utc_time(std::string_view text);

}  // namespace unima::platform
