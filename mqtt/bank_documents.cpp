#include "mqtt/bank_documents.hpp"

#include <algorithm>

#include "platform/utc_time.hpp"
#include "values/value_json.hpp"

namespace unima::mqtt {

std::vector<banks::BankId> published_banks(const values::ValueModel& model) {
  std::vector<banks::BankId> banks;
  for (const auto& layout : model.banks())
    if (!banks::is_write_bank(layout.bank)) banks.push_back(layout.bank);
  return banks;
}

nlohmann::ordered_json bank_values(const values::BankValues& layout, std::span<const values::Value> values, bool online) {
  nlohmann::ordered_json document = nlohmann::ordered_json::object();
  document["online"] = online;
  for (std::size_t i = 0; i < layout.values.size() && i < values.size(); ++i)
    if (values::published(values[i])) document[layout.values[i].name] = values::reading_json(layout.values[i], values[i]);
  return document;
}

nlohmann::ordered_json bank_document(const values::BankValues& layout, std::span<const values::Value> values, bool online,
                                     std::chrono::system_clock::time_point now) {
  std::string time;
  platform::append_utc_time(time, now);
  nlohmann::ordered_json document = {{"time", time}};
  auto changing = bank_values(layout, values, online);
  for (auto& [key, value] : changing.items()) document[key] = std::move(value);
  return document;
}

PublishSchedule::PublishSchedule(std::size_t banks, std::chrono::milliseconds period, bool on_change)
    : period_(period), on_change_(on_change), banks_(banks) {}

std::vector<std::size_t> PublishSchedule::due(std::span<const std::uint64_t> changes, Clock::time_point now,
                                              const StateOf& state_of) {
  const bool full = all_due_ || now - last_full_ >= period_;
  if (full) {
    all_due_ = false;
    last_full_ = now;
  }
  next_due_ = last_full_ + period_;
  std::vector<std::size_t> due;
  for (std::size_t i = 0; i < changes.size() && i < banks_.size(); ++i) {
    auto& bank = banks_[i];
    bank.latest = changes[i];
    const bool changed = on_change_ && bank.latest != bank.examined;
    if (!full && !changed) continue;
    if (!full) {
      const auto when = bank.edge.when(now);
      if (when > now) {  // within its 100 ms: it goes then, with the state it has then
        next_due_ = std::min(next_due_, when);
        continue;
      }
    }
    bank.examined = bank.latest;
    auto state = state_of(i);
    if (!full && state == bank.published) continue;  // a change the document does not show
    due.push_back(i);
    bank.published = std::move(state);
    bank.edge.went(now);
  }
  return due;
}

}  // namespace unima::mqtt
