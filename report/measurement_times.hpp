#pragma once
// When each bank's values were measured (SPEC §21, honest times): the arrival of the
// telegram (or the presence time-out) that last changed what the bank shows, not when a
// document about it went. A document re-sent without a new telegram keeps the time its
// values had; Sparkplug metrics carry it as their timestamp. The caller tells it the
// banks' change counts (banks::RegisterStore::changes) and when the store's latest round
// of changes began (io/store_changes: its first change after the last wake-up, which is
// the arrival of the telegrams that one read brought). Pure: times are passed in.

#include <chrono>
#include <cstdint>
#include <span>
#include <vector>

namespace unima::report {

class MeasurementTimes {
 public:
  using Time = std::chrono::system_clock::time_point;

  /// A bank whose count moved since the last call was measured at `changed_at`; a bank seen
  /// for the first time (or after a new layout: fewer or more banks) at `changed_at` too.
  void note(std::span<const std::uint64_t> changes, Time changed_at);
  /// Bank i's measurement time. Precondition: note() has seen bank i.
  Time of(std::size_t bank) const { return banks_[bank].measured; }

 private:
  struct Bank {
    std::uint64_t changes = 0;
    Time measured{};
  };
  std::vector<Bank> banks_;
};

}  // namespace unima::report
