#pragma once
// The state file's format (SPEC §10): an append-only journal of text lines, readable with
// `cat`, each record checked by its own CRC-32:
//
//   unima-bridge state 1
//   W 3 1234 8c7f0b1e
//   X 0 5 2a41d9c0
//   O 2 77 0f3e51aa          (user output 2 of a write block)
//
// A record is appended and fdatasync'ed before the write it holds is acknowledged, so a
// crash can only tear the records after the last acknowledged one. Compaction rewrites the
// file as the header and one record per set value (by atomic replace).

#include <cstddef>
#include <string>
#include <string_view>

#include "state/state_image.hpp"

namespace unima::state {

inline constexpr std::string_view journal_header = "unima-bridge state 1\n";

std::string encode_record(const PersistedValue& value);
/// The header and one record per set value of `image`.
std::string encode_image(const StateImage& image);

struct LoadedJournal {
  enum class Status {
    ok,         // every line a record (an empty file too)
    torn_tail,  // the last line was torn by a crash: a write never acknowledged, dropped
    damaged,    // a bad record with more after it: the records before it are kept
    foreign,    // not a state journal (another file, another version): nothing is kept
  };
  Status status = Status::ok;
  StateImage image;           // from the records that were read
  std::size_t good_bytes = 0; // the length of the file's part that was read
  std::size_t records = 0;
  std::string problem;        // "line 7: …" when status is not ok
};

LoadedJournal parse_journal(std::string_view bytes);

}  // namespace unima::state
