#include "report/report_schedule.hpp"

#include <algorithm>

#include "report/change_rule.hpp"

namespace unima::report {

ReportSchedule::ReportSchedule(std::size_t banks, Intervals intervals) : intervals_(intervals), banks_(banks) {}

bool ReportSchedule::changed(const Bank& bank, const BankNow& now) {
  if (bank.published_online != now.online || bank.published.size() != now.values.size()) return true;
  for (std::size_t i = 0; i < now.values.size(); ++i)
    if (counts_as_changed(bank.published[i], now.values[i], i < now.deadbands.size() ? now.deadbands[i] : 0)) return true;
  return false;
}

std::vector<std::size_t> ReportSchedule::due(std::span<const std::uint64_t> changes, Clock::time_point now,
                                             const BankNowOf& bank_now) {
  const bool all = std::exchange(all_due_, false);
  next_due_ = now + intervals_.max_interval;
  std::vector<std::size_t> due;
  for (std::size_t i = 0; i < changes.size() && i < banks_.size(); ++i) {
    auto& bank = banks_[i];
    bank.latest = changes[i];
    const bool full = all || !bank.went || now - *bank.went >= intervals_.max_interval;
    const bool moved = (intervals_.on_change && bank.latest != bank.examined) || bank.asked;
    if (!full && moved && now < *bank.went + intervals_.min_interval) {
      // Within its min_interval: it goes then, with the values it has then.
      next_due_ = std::min(next_due_, *bank.went + intervals_.min_interval);
      continue;
    }
    if (full || moved) {
      bank.examined = bank.latest;
      const auto state = bank_now(i);
      if (full || bank.asked || changed(bank, state)) {
        due.push_back(i);
        bank.published.assign(state.values.begin(), state.values.end());
        bank.published_online = state.online;
        bank.went = now;
        bank.asked = false;
        bank.in_full = full;
      }
    }
    next_due_ = std::min(next_due_, *bank.went + intervals_.max_interval);
  }
  return due;
}

}  // namespace unima::report
