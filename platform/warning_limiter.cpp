#include "platform/warning_limiter.hpp"

namespace unima::platform {

bool WarningLimiter::admit(std::string_view group, std::string_view key, Clock::time_point now) {
  if (!period_end_) period_end_ = now + options_.period;
  const auto found = held_.find(KeyView(group, key));
  if (found != held_.end()) {
    ++found->second;
    return false;
  }
  if (keys_ >= options_.max_keys) {
    ++held_[Key(group, "")];
    return false;
  }
  held_.emplace(Key(group, key), 0);
  ++keys_;
  return true;
}

std::vector<WarningLimiter::Held> WarningLimiter::end_period(Clock::time_point now) {
  std::vector<Held> held;
  if (!period_end_ || now < *period_end_) return held;
  for (auto it = held_.begin(); it != held_.end();) {
    if (it->second == 0) {  // quiet since its logged event: forgotten, the next is logged again
      if (!it->first.second.empty()) --keys_;
      it = held_.erase(it);
      continue;
    }
    held.push_back({it->first.first, it->first.second, it->second});
    it->second = 0;  // still counted, not logged, in the next period
    ++it;
  }
  // Periods follow each other while keys are counted; late calls do not shift them.
  if (held.empty()) {
    period_end_.reset();
  } else {
    while (*period_end_ <= now) *period_end_ += options_.period;
  }
  return held;
}

}  // namespace unima::platform
