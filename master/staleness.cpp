#include "master/staleness.hpp"

namespace unima::master {

Staleness::Staleness(std::vector<std::optional<Clock::duration>> limits, Clock::time_point start)
    : limits_(std::move(limits)), last_good_(limits_.size(), start), stale_(limits_.size(), false) {}

void Staleness::refreshed(std::size_t block, Clock::time_point now) {
  last_good_[block] = now;
  stale_[block] = false;
}

std::vector<std::size_t> Staleness::expire(Clock::time_point now) {
  std::vector<std::size_t> gone;
  for (std::size_t i = 0; i < limits_.size(); ++i) {
    if (!limits_[i] || stale_[i] || last_good_[i] + *limits_[i] > now) continue;
    stale_[i] = true;
    gone.push_back(i);
  }
  return gone;
}

std::optional<Staleness::Clock::time_point> Staleness::next_expiry() const {
  std::optional<Clock::time_point> next;
  for (std::size_t i = 0; i < limits_.size(); ++i) {
    if (!limits_[i] || stale_[i]) continue;
    const auto limit = last_good_[i] + *limits_[i];
    if (!next || limit < *next) next = limit;
  }
  return next;
}

}  // namespace unima::master
