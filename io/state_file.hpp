#pragma once
// The state file on the disk (SPEC §10): what masters wrote into W, X and the write
// blocks' outputs, appended as journal records (state/state_journal) and fdatasync'ed
// before those writes take effect or are acknowledged. A write is kept whole: its records
// go into one batch, never split over two fdatasyncs, and are marked as one write, so a
// crash in the middle of the append loses the write whole. Once its batch is durable the
// write is committed (banks::WritePath::commit: into the store, and so to UnimaBUS), then
// its waiters hear of it (`when_durable`); a batch the disk refuses commits nothing, its
// writes are refused (the ports answer exception 04), the log says so once per outage,
// and the next batch rewrites the file from what it held before. The records that come
// while one fdatasync runs share the next (group commit), which starts as soon as that one
// returns. A batch's writes are committed and answered a slice at a time, each slice its
// own turn of the loop, so that a Modbus request between them is served.
//
// fdatasync blocks for milliseconds, longer on a busy or failing disk, and the loop must
// never wait for it: the writes and syncs run on one thread of this class (why and how:
// io/state_file.cpp); everything else, including every callback, happens on the loop.

#include <cstdint>
#include <deque>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <span>
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
    std::uint64_t records = 0;   // values recorded since the start (durable or refused)
    std::uint64_t syncs = 0;     // fdatasync calls that succeeded
    std::uint64_t failures = 0;  // batches whose write or sync failed: their writes refused
  };

  /// What becomes of kept writes, on the loop. `commit` gets each write's values once they
  /// are durable, in the order kept, before its waiters hear of it; `refused` is told of
  /// every batch the disk refused (the Error bit, C+0x13 bit 15).
  struct Outcome {
    std::function<void(std::span<const banks::WrittenValue>)> commit;
    std::function<void()> refused;
  };

  /// Loads `path` (absent: nothing set) and rewrites it compacted, so it is known writable
  /// before any write is taken. A foreign or damaged file (a bad record anywhere but in
  /// the write a crash cut short at its end) is kept aside as `<path>.corrupt-<UTC time>`
  /// and logged, and nothing of it is restored. Throws std::runtime_error naming the path
  /// when it cannot be used.
  StateFile(asio::io_context& io, std::filesystem::path path);
  /// Writes and syncs what is still pending (a clean stop loses nothing), then stops.
  ~StateFile();
  StateFile(const StateFile&) = delete;
  StateFile& operator=(const StateFile&) = delete;

  /// Writes committed and answered in one turn of the loop at most; fewer when their answers
  /// cost more than the turn's budget (io/loop_turn.hpp: an MQTT command's answer is a
  /// publish), so that a Modbus request waits for one slice between two of its chances.
  static constexpr std::size_t writes_per_slice = 64;

  /// What the file held at the start.
  const state::StateImage& restored() const { return restored_; }
  const std::filesystem::path& path() const { return path_; }

  void set_outcome(Outcome outcome);

  /// Appends a write's values (W, X, or C at a user output's offset) as one write; on the
  /// disk after the next fdatasync that begins. Returns the write's number.
  std::uint64_t keep(std::span<const banks::WrittenValue> write) override;
  std::optional<std::uint16_t> pending(banks::BankId bank, std::uint16_t offset) const override;
  /// Calls `done` once write number `sequence` is durable (and committed), or refused.
  /// Asked in the loop's turn that kept the write (every entry point does), before its
  /// batch can have completed: a refused write asked later would look durable.
  void when_durable(std::uint64_t sequence, Done done);
  Counters counters() const;

 private:
  struct Shared;  // the loop's side and the sync thread's side, io/state_file.cpp
  std::filesystem::path path_;
  state::StateImage restored_;
  std::shared_ptr<Shared> shared_;
};

/// How every entry point that takes a write answers (SPEC §10): at once when the write
/// kept nothing (`kept_as` 0, or no state file), else once the state file holds it and it
/// took effect — `answer(true)` — or could not take it — `answer(false)`: nothing changed,
/// and the write is refused (Modbus exception 04, modbus::refuse_unkept_write).
template <typename Answer>
void answer_once_durable(StateFile* state, std::uint64_t kept_as, Answer&& answer) {
  if (state == nullptr || kept_as == 0) return answer(true);
  state->when_durable(kept_as, std::forward<Answer>(answer));
}

}  // namespace unima::io
