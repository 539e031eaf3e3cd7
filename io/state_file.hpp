#pragma once
// The state file on the disk (SPEC §10): what masters wrote into W, X and the write
// blocks' outputs, appended as journal records (state/state_journal) and fdatasync'ed
// before those writes are acknowledged. Records that arrive in one turn of the loop share
// one fdatasync (group commit): the ports answer a write only once `when_durable` says so.
//
// fdatasync blocks for milliseconds, longer on a busy or failing disk, and the loop must
// never wait for it: the writes and syncs run on one thread of this class, handed a batch
// at a time; everything else, including every callback, happens on the loop.

#include <cstdint>
#include <deque>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>

#include "platform/asio.hpp"
#include "state/state_image.hpp"

namespace unima::io {

class StateFile {
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

  /// Appends a value; on the disk after this turn of the loop's group commit.
  void record(const state::PersistedValue& value);
  /// The number of the last record: `when_durable(recorded(), …)` waits for all so far.
  std::uint64_t recorded() const;
  /// Calls `done` once record number `sequence` is durable, or failed; at once when it is.
  void when_durable(std::uint64_t sequence, Done done);
  Counters counters() const;

 private:
  struct Shared;  // the loop's side and the sync thread's side, io/state_file.cpp
  std::filesystem::path path_;
  state::StateImage restored_;
  std::shared_ptr<Shared> shared_;
};

}  // namespace unima::io
