#pragma once
// A polled value that is not refreshed within its block's `stale_after` reads "not
// measured" (0x7FFF) until the next good answer (docs/master.md, "Staleness"). Pure: the
// caller passes the time and arms one timer at next_expiry().

#include <chrono>
#include <cstddef>
#include <optional>
#include <vector>

namespace unima::master {

class Staleness {
 public:
  using Clock = std::chrono::steady_clock;

  /// One limit per block; nullopt for a block that never goes stale (a write). The start
  /// counts as a refresh of every block.
  Staleness(std::vector<std::optional<Clock::duration>> limits, Clock::time_point start);

  /// A good value of `block` arrived at `now`.
  void refreshed(std::size_t block, Clock::time_point now);
  /// The blocks that went stale by `now`, each reported once until it is refreshed.
  std::vector<std::size_t> expire(Clock::time_point now);
  /// The moment the next fresh block goes stale if nothing arrives; nullopt when none can.
  std::optional<Clock::time_point> next_expiry() const;
  bool stale(std::size_t block) const { return stale_[block]; }

 private:
  std::vector<std::optional<Clock::duration>> limits_;
  std::vector<Clock::time_point> last_good_;
  std::vector<bool> stale_;
};

}  // namespace unima::master
