#pragma once
// The state file's format (SPEC §10): an append-only journal of text lines, readable with
// `cat`, each record checked by its own CRC-32:
//
//   unima-bridge state 1
//   W 3 1234 8c7f0b1e
//   X 0 5 2a41d9c0
//   O 2 77 0f3e51aa          (user output 2 of a write block)
//   W 10 7 + 5d1c02e4        (a write of W+10..W+12: `+` says the next record is of the
//   W 11 8 + 0b6a7f31         same write; its last record has none)
//   W 12 9 d2e0c51a
//
// The records of a write are appended and fdatasync'ed together, before the write is
// acknowledged, so a crash can only tear what comes after the last acknowledged write: a
// line cut short, or a write whose last record is missing. Such a tail was never
// acknowledged and is dropped whole, so a write comes back whole or not at all. Anything
// else that is not a record is damage, and then nothing of the file is trusted (SPEC §10:
// set aside, start with nothing set). Compaction rewrites the file as the header and one
// record per set value (by atomic replace). Files without `+` (written before writes were
// grouped) read the same: every record a write of its own.

#include <cstddef>
#include <string>
#include <string_view>

#include "state/checked_lines.hpp"
#include "state/state_image.hpp"

namespace unima::state {

inline constexpr std::string_view journal_header = "unima-bridge state 1\n";

/// One record; `continued`: the next record belongs to the same write.
std::string encode_record(const PersistedValue& value, bool continued = false);
/// The header and one record per set value of `image`.
std::string encode_image(const StateImage& image);

struct LoadedJournal {
  /// ok: every line a record of a whole write (an empty file too); torn_tail: a crash cut
  /// the last write short (its last line, or its last records), never acknowledged,
  /// dropped whole, the writes before it kept; damaged: a bad record that is not the last
  /// line, nothing kept; foreign: not a state journal, nothing kept.
  using Status = JournalStatus;
  Status status = Status::ok;
  StateImage image;           // from the whole writes read; empty unless ok or torn_tail
  std::size_t good_bytes = 0; // the length of the file's part whose writes are in `image`
  std::size_t records = 0;    // the records of those writes
  std::string problem;        // "line 7: …" when status is not ok
};

LoadedJournal parse_journal(std::string_view bytes);

}  // namespace unima::state
