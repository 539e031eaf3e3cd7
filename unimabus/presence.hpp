#pragma once
// On-line tracking (SPEC §6): a device is on-line while its telegrams arrive within
// `offline_after`. Pure: the caller passes the time and arms one timer at next_expiry(),
// so an idle bridge never wakes up for nothing.

#include <array>
#include <chrono>
#include <optional>
#include <vector>

#include "banks/bank_id.hpp"

namespace unima::unimabus {

class Presence {
 public:
  using Clock = std::chrono::steady_clock;

  explicit Presence(Clock::duration offline_after) : offline_after_(offline_after) {}

  /// Records a telegram; true when the bank was off-line until now.
  bool heard(banks::BankId bank, Clock::time_point now);
  /// The banks whose last telegram is older than offline_after at `now`; they are off-line now.
  std::vector<banks::BankId> expire(Clock::time_point now);
  /// When the next on-line bank will go off-line if nothing is heard.
  std::optional<Clock::time_point> next_expiry() const;
  bool online(banks::BankId bank) const { return last_heard_[index_of(bank)].has_value(); }

 private:
  Clock::duration offline_after_;
  std::array<std::optional<Clock::time_point>, banks::bank_count> last_heard_{};
};

}  // namespace unima::unimabus
