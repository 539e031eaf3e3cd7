#pragma once
// The state file on the disk (SPEC §10): what masters wrote into W, X and the write
// blocks' outputs, appended as journal records (state/state_journal) and fdatasync'ed
// before those writes are acknowledged: the ports answer a write only once `when_durable`
// says so. The records that come while one fdatasync runs share the next (group commit),
// which starts as soon as that one returns.
//
// fdatasync blocks for milliseconds, longer on a busy or failing disk, and the loop must
// never wait for it: the writes and syncs run on one thread of this class (why and how:
// io/state_file.cpp); everything else, including every callback, happens on the loop.

#include <cstdint>
#include <deque>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <utility>

#include "banks/write_path.hpp"
#include "platform/asio.hpp"
#include "state/state_image.hpp"

namespace unima::io {

/// The journal of banks::WritePath on the disk.
class StateFile final : public banks::WriteJournal {
 public:
  /// Called on the loop once the record is on the disk (true), or its write failed (false:
  /// the write must not be acknowledged).
  using Done = std::function<void(bool durable)>;

  struct Counters {
    std::uint64_t records = 0;   // values recorded since the start
    std::uint64_t syncs = 0;     // fdatasync calls that succeeded
    std::uint64_t failures = 0;  // batches whose write or sync failed
  };

  /// Loads `path` (absent: nothing set) and rewrites it compacted, so it is known writable
  /// before any write is taken. A foreign or damaged file is kept aside as
  /// `<path>.corrupt-<UTC time>` and logged; a damaged one still gives the values recorded
  /// before the damage. Throws std::runtime_error naming the path when it cannot be used.
  StateFile(asio::io_context& io, std::filesystem::path path);
  /// Writes and syncs what is still pending (a clean stop loses nothing), then stops.
  ~StateFile();
  StateFile(const StateFile&) = delete;
  StateFile& operator=(const StateFile&) = delete;

  /// What the file held at the start.
  const state::StateImage& restored() const { return restored_; }
  const std::filesystem::path& path() const { return path_; }

  /// Appends a written value (W, X, or C at a user output's offset); on the disk after the
  /// next fdatasync that begins. Returns its record's number.
  std::uint64_t keep(banks::BankId bank, std::uint16_t offset, std::uint16_t value) override;
  /// Calls `done` once record number `sequence` is durable, or failed; at once when it is.
  void when_durable(std::uint64_t sequence, Done done);
  Counters counters() const;

 private:
  void record(const state::PersistedValue& value);

  struct Shared;  // the loop's side and the sync thread's side, io/state_file.cpp
  std::filesystem::path path_;
  state::StateImage restored_;
  std::shared_ptr<Shared> shared_;
};

/// How every entry point that takes a write answers (SPEC §10): at once when the write
/// kept nothing (`kept_as` 0, or no state file), else once the state file holds it —
/// `answer(true)` — or could not take it — `answer(false)`: it must not be acknowledged.
template <typename Answer>
void answer_once_durable(StateFile* state, std::uint64_t kept_as, Answer&& answer) {
  if (state == nullptr || kept_as == 0) return answer(true);
  state->when_durable(kept_as, std::forward<Answer>(answer));
}

}  // namespace unima::io
