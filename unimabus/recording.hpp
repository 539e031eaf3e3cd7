#pragma once
// Recordings of UnimaBUS telegrams (SPEC §6): what `record` writes on a site and `replay`
// plays in the office. A recording is JSON lines, each a feed telegram plus "t", seconds
// since the recording began, non-decreasing; blank lines are skipped. Pure.

#include <chrono>
#include <cstddef>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "unimabus/feed_codec.hpp"

namespace unima::unimabus {

struct Recording {
  struct Entry {
    double t = 0;           // seconds since the recording began
    std::size_t line = 0;   // 1-based, for messages
    Telegram telegram;
  };
  std::string origin;  // the file, for messages
  std::vector<Entry> entries;

  double duration() const { return entries.empty() ? 0.0 : entries.back().t; }
  friend bool operator==(const Recording&, const Recording&);
};

class RecordingError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Parses a whole recording; throws RecordingError "origin:line: why" at the first bad line
/// or decreasing "t".
Recording parse_recording(std::string_view text, std::string_view origin);

/// Which telegram of a recording is due when, played `speed` times as fast, from the
/// start again when `loop` is set: one average interval between lines after the last line.
/// The caller owns the clock: it asks when the next one is due, waits, and takes those due.
class ReplaySchedule {
 public:
  using Duration = std::chrono::nanoseconds;
  /// A pass of a looped recording lasts at least this long, so that a recording whose
  /// telegrams all have t = 0 does not replay without end in one instant.
  static constexpr Duration shortest_pass = std::chrono::milliseconds(100);
  /// No telegram is due later: "t" may be 1e9 s and the speed 0.001, but nanoseconds in 64
  /// bits reach only 292 years, and the transport adds its start to the time it is given.
  static constexpr Duration latest_due = std::chrono::hours(24 * 365 * 100);

  ReplaySchedule(const Recording& recording, double speed, bool loop);

  /// When the next telegram is due, since the start; nullopt when the recording is over.
  std::optional<Duration> next_due() const;
  /// The next telegram if it is due at `elapsed`, else nullptr; each is taken once.
  const Recording::Entry* take_due(Duration elapsed);

 private:
  Duration due(std::size_t index, std::size_t pass) const;

  const Recording& recording_;
  double speed_;
  bool loop_;
  std::size_t index_ = 0;
  std::size_t pass_ = 0;
};

}  // namespace unima::unimabus
