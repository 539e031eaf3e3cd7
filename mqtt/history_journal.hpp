#pragma once
// The MQTT history buffer's format (SPEC §15): while the broker is unreachable, each bank
// document that would have been published is appended to a journal of text lines,
// readable with `cat`, each line checked by its own CRC-32 (state/checked_lines, the
// state file's format):
//
//   unima-bridge mqtt history 1
//   E 1 D1 {"time":"2026-11-24T20:48:09.927231Z","online":true,…} 5d1c02e4
//   E 2 C {"time":"2026-11-24T20:48:10.027117Z",…} 0b6a7f31
//   A 1 8c7f0b1e              (the broker acknowledged every entry up to 1)
//
// An entry is `E <sequence> <bank> <document>`: the document exactly as it would have been
// published, its original "time" in it (JSON as the bridge writes it holds no newline).
// Sequences grow by one per entry. `A <sequence>` says the broker has acknowledged the
// history up to that entry, so a restart sends only what follows. The file is appended
// and synced at least once a second, so a crash tears at most its last line: a torn tail,
// dropped. A bad line anywhere else is damage, and the file is set aside whole (as the
// state file, SPEC §10). Pure: the file and its thread live in io/mqtt/history_buffer.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "state/checked_lines.hpp"

namespace unima::mqtt {

inline constexpr std::string_view history_header = "unima-bridge mqtt history 1\n";

struct HistoryEntry {
  std::uint64_t sequence = 0;
  std::string bank;      // "D1", "C", …: the topic is <prefix>/history/<bank>
  std::string document;  // the payload
  bool operator==(const HistoryEntry&) const = default;
};

/// The entry's line, its newline included.
std::string encode_history_entry(const HistoryEntry& entry);
/// The line that says every entry up to `sequence` was acknowledged.
std::string encode_history_acknowledged(std::uint64_t sequence);
/// An entry's line (its newline optional) when it is a whole, good entry.
std::optional<HistoryEntry> parse_history_entry(std::string_view line);

/// Where an entry not yet acknowledged lies in the file.
struct HistoryPlace {
  std::uint64_t sequence = 0;
  std::uint64_t offset = 0;  // of its line
  std::uint64_t size = 0;    // of its line, the newline included
  bool operator==(const HistoryPlace&) const = default;
};

struct LoadedHistory {
  /// ok: every line good (an empty file too); torn_tail: the last line cut short by a
  /// crash, dropped, the lines before it kept; damaged: a bad line that is not the last,
  /// nothing kept; foreign: not a history buffer, nothing kept.
  using Status = state::JournalStatus;
  Status status = Status::ok;
  std::vector<HistoryPlace> pending;  // the entries after the last acknowledged, oldest first
  std::uint64_t last_sequence = 0;    // of the last entry read (acknowledged or not)
  std::uint64_t good_bytes = 0;       // the file's part that was read whole
  std::string problem;                // "line 7: …" when status is not ok
};

LoadedHistory parse_history(std::string_view bytes);

/// The buffer's rule when it is full (SPEC §15: the oldest entries go). `sizes` are the
/// entries' lines, oldest first, that the buffer would hold; `room` is what max_size leaves
/// for them. None go while they fit; else the oldest go until the rest leave an eighth of
/// the room free, so that a full buffer is rewritten once per eighth of its size taken in,
/// not for every new entry — unless that would leave nothing: then the oldest go only until
/// the rest fit the room, so the newest entries stay whenever one fits at all. Returns how
/// many of the oldest go.
std::size_t oldest_to_drop(std::span<const std::uint64_t> sizes, std::uint64_t room);

}  // namespace unima::mqtt
