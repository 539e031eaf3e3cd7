// Fuzz target: a state file as the daemon finds it at start (SPEC §10): whatever a crash,
// a full disk or a hand edit left, state::parse_journal reads it, as io/state_file does
// before it rewrites the file from what was read and appends to it.
//
// Input: the file's bytes, all of them.

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "fuzz/fuzz_check.hpp"
#include "state/state_journal.hpp"

namespace {

using namespace unima;
using Status = state::LoadedJournal::Status;

// What the daemon does next with what was read: it keeps the good part, and new records
// follow it. Both must read back as they were, whatever came before; a write of several
// records is taken whole, and a part of one never.
void continue_from(std::string_view bytes, const state::LoadedJournal& loaded) {
  const auto kept = state::parse_journal(bytes.substr(0, loaded.good_bytes));
  FUZZ_CHECK(kept.status == Status::ok);
  FUZZ_CHECK(kept.image == loaded.image && kept.records == loaded.records);

  const auto compacted = state::encode_image(loaded.image);
  const auto reread = state::parse_journal(compacted);
  FUZZ_CHECK(reread.status == Status::ok && reread.good_bytes == compacted.size());
  FUZZ_CHECK(reread.image == loaded.image && reread.records == loaded.image.values().size());

  // One more acknowledged write after the restart: the last value of a register wins.
  const state::PersistedValue next{state::PersistedValue::Kind::w, 7, static_cast<std::uint16_t>(bytes.size())};
  const auto appended = state::parse_journal(compacted + state::encode_record(next));
  auto expected = loaded.image;
  expected.apply(next);
  FUZZ_CHECK(appended.status == Status::ok && appended.image == expected);

  const state::PersistedValue also{state::PersistedValue::Kind::x, 0, static_cast<std::uint16_t>(~bytes.size())};
  const auto two = state::encode_record(next, true) + state::encode_record(also);
  const auto whole = state::parse_journal(compacted + two);
  expected.apply(also);
  FUZZ_CHECK(whole.status == Status::ok && whole.image == expected);
  const auto cut = state::parse_journal(compacted + two.substr(0, two.size() - 1));
  FUZZ_CHECK(cut.status == Status::torn_tail && cut.image == loaded.image);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  const auto loaded = state::parse_journal(bytes);

  FUZZ_CHECK(loaded.good_bytes <= size);
  FUZZ_CHECK(loaded.problem.empty() == (loaded.status == Status::ok));
  if (loaded.status == Status::ok) FUZZ_CHECK(loaded.good_bytes == size);
  if (loaded.status == Status::foreign || loaded.good_bytes == 0)
    FUZZ_CHECK(loaded.records == 0 && loaded.image.empty());
  // SPEC §10: nothing of a damaged file is restored.
  if (loaded.status == Status::damaged) FUZZ_CHECK(loaded.good_bytes == 0 && loaded.image.empty());
  // "line N: why", N from 1: what the log and the set-aside file's message say.
  if (!loaded.problem.empty()) FUZZ_CHECK(loaded.problem.starts_with("line ") && loaded.problem[5] >= '1' && loaded.problem[5] <= '9');
  for (const auto& value : loaded.image.values()) FUZZ_CHECK(state::valid_index(value.kind, value.index));

  continue_from(bytes, loaded);
  return 0;
}
