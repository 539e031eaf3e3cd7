#include "state/checked_lines.hpp"

#include <charconv>
#include <cstdint>

#include <fmt/format.h>

#include "state/crc32.hpp"

namespace unima::state {

std::string checked_line(std::string_view body) { return fmt::format("{} {:08x}\n", body, crc32(body)); }

std::optional<std::string_view> checked_body(std::string_view line, std::string& why) {
  if (line.ends_with('\n')) line.remove_suffix(1);
  const auto last_space = line.rfind(' ');
  std::uint32_t crc = 0;
  const auto digits = last_space == std::string_view::npos ? std::string_view() : line.substr(last_space + 1);
  const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), crc, 16);
  if (digits.size() != 8 || ec != std::errc() || end != digits.data() + digits.size()) {
    why = "no checksum";
    return std::nullopt;
  }
  const auto body = line.substr(0, last_space);
  if (crc32(body) != crc) {
    why = "checksum mismatch";
    return std::nullopt;
  }
  return body;
}

JournalWalk walk_journal(std::string_view bytes, std::string_view header, std::string_view name,
                         std::string_view group_torn, const LineReader& read) {
  JournalWalk walk;
  if (bytes.empty()) return walk;
  if (!bytes.starts_with(header)) {
    // A crash while a new file's header was written leaves a part of it: nothing was in it.
    const auto family = header.substr(0, header.rfind(' ') + 1);  // "unima-bridge state "
    walk.status = header.starts_with(bytes) ? JournalStatus::torn_tail : JournalStatus::foreign;
    walk.problem = walk.status == JournalStatus::torn_tail ? "line 1: a torn header"
                   : bytes.starts_with(family) ? fmt::format("line 1: another version of the {}", name)
                                               : fmt::format("line 1: not a unima-bridge {}", name);
    return walk;
  }
  std::size_t at = header.size();
  walk.good_bytes = at;
  std::size_t line_number = 1;
  bool in_group = false;
  while (at < bytes.size()) {
    ++line_number;
    const auto newline = bytes.find('\n', at);
    const bool last = newline == std::string_view::npos || newline + 1 == bytes.size();
    std::string why = "no end of line";
    std::optional<std::string_view> body;
    if (newline != std::string_view::npos) body = checked_body(bytes.substr(at, newline - at), why);
    auto verdict = body ? read(*body, at, newline + 1 - at) : LineVerdict{LineVerdict::Kind::bad, why};
    if (verdict.kind == LineVerdict::Kind::bad) {
      // Only a line that fails its own check can be a write a crash cut short: one whose
      // checksum holds but whose content is not a record (a register out of range) was
      // written so, and the file is not ours to trust, last line or not (issue 43).
      walk.status = last && !body ? JournalStatus::torn_tail : JournalStatus::damaged;
      walk.problem = fmt::format("line {}: {}", line_number, verdict.why);
      break;
    }
    at = newline + 1;
    in_group = verdict.kind == LineVerdict::Kind::continued;
    if (!in_group) walk.good_bytes = at;
  }
  if (walk.status == JournalStatus::ok && in_group) {
    walk.status = JournalStatus::torn_tail;
    walk.problem = fmt::format("line {}: {}", line_number, group_torn);
  }
  if (walk.status == JournalStatus::damaged) walk.good_bytes = 0;
  return walk;
}

}  // namespace unima::state
