#pragma once
// How often a warning a peer can cause is logged (SPEC §10: "first one, then a count every
// minute"), so that no peer — nor many of them — can flood the log.
//
// Periods are shared by every key: the first event opens one, and when it ends each key
// that had more events reports how many, then goes on being counted in the next period;
// a key that stayed quiet is forgotten, so its next event is logged in full again. When
// no key had more, no period is open and nothing needs waking. At most `max_keys` keys
// are told apart in a period; events of further keys are counted together, per group.
//
// Pure: the caller passes the time, and logs what it is told to.

#include <chrono>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace unima::platform {

class WarningLimiter {
 public:
  using Clock = std::chrono::steady_clock;
  struct Options {
    Clock::duration period = std::chrono::minutes(1);
    std::size_t max_keys = 100;
  };

  WarningLimiter() : WarningLimiter(Options{}) {}
  explicit WarningLimiter(Options options) : options_(options) {}

  /// An event of `key` (e.g. a peer's address) in `group` (e.g. the kind of warning) at
  /// `now`: true when it is to be logged, false when it is only counted.
  bool admit(std::string_view group, std::string_view key, Clock::time_point now);

  /// When the open period ends, nullopt when none is open.
  std::optional<Clock::time_point> period_end() const { return period_end_; }

  struct Held {
    std::string group;
    std::string key;  // empty: the keys past max_keys, together
    std::uint64_t count;
    bool operator==(const Held&) const = default;
  };
  /// Ends the period if it has ended by `now`: the events each key had after its logged
  /// one, to be logged as counts (in the order of group and key).
  std::vector<Held> end_period(Clock::time_point now);

  const Options& options() const { return options_; }

 private:
  using Key = std::pair<std::string, std::string>;  // group, key ("" for the others of a group)
  using KeyView = std::pair<std::string_view, std::string_view>;
  // Looks keys up without copying them into strings: one event, no allocation.
  struct KeyOrder {
    using is_transparent = void;
    static KeyView view(const Key& key) { return {key.first, key.second}; }
    static KeyView view(const KeyView& key) { return key; }
    template <typename A, typename B>
    bool operator()(const A& a, const B& b) const { return view(a) < view(b); }
  };

  Options options_;
  std::optional<Clock::time_point> period_end_;
  std::map<Key, std::uint64_t, KeyOrder> held_;  // every key seen in the period: its events not logged
  std::size_t keys_ = 0;  // of held_, those that are a peer's own (not the others' of a group)
};

}  // namespace unima::platform
