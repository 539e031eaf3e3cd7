#include "unimabus/presence.hpp"

namespace unima::unimabus {

bool Presence::heard(banks::BankId bank, Clock::time_point now) {
  auto& last = last_heard_[index_of(bank)];
  const bool was_offline = !last.has_value();
  last = now;
  return was_offline;
}

std::vector<banks::BankId> Presence::expire(Clock::time_point now) {
  std::vector<banks::BankId> gone;
  for (banks::BankId bank : banks::all_banks) {
    auto& last = last_heard_[index_of(bank)];
    if (last && now - *last >= offline_after_) {
      last.reset();
      gone.push_back(bank);
    }
  }
  return gone;
}

std::optional<Presence::Clock::time_point> Presence::next_expiry() const {
  std::optional<Clock::time_point> next;
  for (const auto& last : last_heard_)
    if (last && (!next || *last + offline_after_ < *next)) next = *last + offline_after_;
  return next;
}

}  // namespace unima::unimabus
