#include "unimabus/telegram_intake.hpp"

namespace unima::unimabus {

TelegramIntake::Taken TelegramIntake::take(const Telegram& telegram, Clock::time_point now) {
  last_telegram_ = now;
  ++counts_.received;
  if (recording_) recording_->record(telegram, now);
  auto outcome = router_.apply(telegram);
  Taken taken{std::move(outcome.error), {}};
  if (outcome.ignored) ++counts_.ignored;
  if (!taken.error.empty()) ++counts_.refused;
  for (banks::BankId bank : outcome.updated) {
    ++counts_.taken[banks::index_of(bank)];
    if (presence_.heard(bank, now)) {
      store_.set_online(bank, true);
      taken.changes.push_back({bank, true});
    }
  }
  return taken;
}

std::vector<TelegramIntake::PresenceChange> TelegramIntake::expire(Clock::time_point now) {
  std::vector<PresenceChange> changes;
  for (banks::BankId bank : presence_.expire(now)) {
    store_.set_online(bank, false);
    changes.push_back({bank, false});
  }
  return changes;
}

std::vector<TelegramIntake::PresenceChange> TelegramIntake::take_over(const TelegramIntake& old, Clock::time_point now) {
  std::vector<PresenceChange> changes;
  // The store kept a bank's values (and its on-line flag) only where its table did not
  // change: there the device is still the one that was heard.
  for (banks::BankId bank : banks::all_banks) {
    if (old.presence_.online(bank) && store_.online(bank)) {
      presence_.heard(bank, now);
      continue;
    }
    if (store_.online(bank) || old.presence_.online(bank)) changes.push_back({bank, false});
    store_.set_online(bank, false);
  }
  counts_ = old.counts_;
  last_telegram_ = old.last_telegram_;
  return changes;
}

}  // namespace unima::unimabus
