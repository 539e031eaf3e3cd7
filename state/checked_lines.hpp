#pragma once
// The one format of the bridge's journals — the state file (state/state_journal, SPEC §10)
// and the MQTT history buffer (mqtt/history_journal, SPEC §15): a header line naming the
// file and its version, then text lines, each `<body> <crc32 as 8 hex digits>\n`, appended.
// A crash can only tear the end: a line cut short, or a group of lines (one write) whose
// last line is missing. That tail was never acknowledged and is dropped. Anything else
// that is not a good line is damage, and then nothing of the file is trusted.
//
// This walks the lines and judges the file; what a line's body means is the caller's.
// Pure: the files and their syncs live in io/.

#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <string_view>

namespace unima::state {

/// `body` as a line of a journal: the body, a space, its CRC-32 in hex and a newline.
std::string checked_line(std::string_view body);
/// A line's body (the line with or without its newline) when its CRC-32 holds; else
/// nullopt, and `why` says what is wrong.
std::optional<std::string_view> checked_body(std::string_view line, std::string& why);

enum class JournalStatus {
  ok,         // every line good and every group whole (an empty file too)
  torn_tail,  // a crash cut the last line or the last group short: dropped, the rest kept
  damaged,    // a bad line that is not the last: nothing is kept
  foreign,    // not this journal (another file, another version): nothing is kept
};

/// What the caller makes of one good line's body.
struct LineVerdict {
  enum class Kind { whole, continued, bad };
  Kind kind = Kind::whole;  // continued: the next line belongs to the same group
  std::string why;          // bad: what is wrong with it
};
/// Called with each line whose checksum holds, in order: its body, and where the line
/// lies in the file (offset, size with its newline).
using LineReader = std::function<LineVerdict(std::string_view body, std::size_t offset, std::size_t size)>;

struct JournalWalk {
  JournalStatus status = JournalStatus::ok;
  std::size_t good_bytes = 0;  // the file's part up to the end of its last whole group
  std::string problem;         // "line 7: …" when status is not ok
};

/// Walks `bytes`, a journal whose first line is `header` (e.g. "unima-bridge state 1\n";
/// `name`, e.g. "state file", words the problems). `group_torn`: the problem when the file
/// ends inside a group. The caller drops what `read` took past good_bytes, and everything
/// when the status is damaged or foreign.
JournalWalk walk_journal(std::string_view bytes, std::string_view header, std::string_view name,
                         std::string_view group_torn, const LineReader& read);

}  // namespace unima::state
