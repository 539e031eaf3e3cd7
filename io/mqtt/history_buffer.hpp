#pragma once
// The MQTT history buffer on the disk (SPEC §15, `mqtt.buffer`): the bank documents made
// while the broker is unreachable, appended as journal entries (mqtt/history_journal) and
// read back oldest first once it is there again. At most `max_size` bytes: when full, the
// oldest entries are dropped and counted. What the broker acknowledged is marked in the
// journal, so a restart sends only what follows.
//
// The loop never waits for the disk: the entries it hands over are written and
// fdatasync'ed by a thread of this class once a second — at least once a second, so that
// kill -9 loses at most the last second, and at most once a second, so that a long outage
// costs the disk one sync per second however many documents it brings (why and how:
// io/mqtt/history_buffer.cpp). Reads for the loop run on the same thread; their results,
// like everything else the loop sees, come back on the loop.

#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "mqtt/history_journal.hpp"
#include "platform/asio.hpp"

namespace unima::io {

class HistoryBuffer {
 public:
  struct Counters {
    std::uint64_t bytes = 0;     // of the entries written and not yet acknowledged
    std::uint64_t messages = 0;  // those entries
    std::uint64_t dropped = 0;   // entries dropped since the start because the buffer was full
    std::uint64_t syncs = 0;     // fdatasync calls (a rewrite's included)
    std::uint64_t failures = 0;  // appends the disk refused: their entries are lost
  };

  /// Loads `path` (absent: begun empty). A torn last line is dropped; a foreign or damaged
  /// file is kept aside as `<path>.corrupt-<UTC time>`, logged, and a new one begun. Throws
  /// std::runtime_error naming the path when it cannot be used.
  HistoryBuffer(asio::io_context& io, std::filesystem::path path, std::uint64_t max_size);
  /// Writes and syncs what was handed over (a clean stop loses nothing), then stops.
  ~HistoryBuffer();
  HistoryBuffer(const HistoryBuffer&) = delete;
  HistoryBuffer& operator=(const HistoryBuffer&) = delete;

  const std::filesystem::path& path() const { return path_; }
  /// The last entry the journal said was acknowledged when it was loaded.
  std::uint64_t delivered_at_start() const { return delivered_at_start_; }

  /// A document that would have been published on <prefix>/<bank>; on the disk within a second.
  void append(std::string_view bank, std::string document);
  using Entries = std::function<void(std::vector<mqtt::HistoryEntry> entries)>;
  /// Up to `count` entries after sequence `after`, oldest first, handed to `done` on the
  /// loop; fewer (none) when there are no more.
  void read(std::uint64_t after, std::size_t count, Entries done);
  /// Every entry up to `sequence` is delivered: marked in the journal within a second, and
  /// no longer counted or read.
  void acknowledge(std::uint64_t sequence);
  Counters counters() const;

 private:
  struct Shared;  // the loop's side and the thread's side, io/mqtt/history_buffer.cpp
  std::filesystem::path path_;
  std::uint64_t delivered_at_start_ = 0;
  std::shared_ptr<Shared> shared_;
};

}  // namespace unima::io
