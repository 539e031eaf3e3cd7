#include "mqtt/bank_documents.hpp"

#include "monitor/monitor_line.hpp"
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
  monitor::append_utc_time(time, now);
  nlohmann::ordered_json document = {{"time", time}};
  auto changing = bank_values(layout, values, online);
  for (auto& [key, value] : changing.items()) document[key] = std::move(value);
  return document;
}

PublishSchedule::PublishSchedule(std::size_t banks, std::chrono::milliseconds period, bool on_change)
    : period_(period), on_change_(on_change), published_(banks), published_at_(banks) {}

std::vector<std::size_t> PublishSchedule::due(const std::vector<std::string>& states, Clock::time_point now) {
  const bool full = all_due_ || now - last_full_ >= period_;
  if (full) {
    all_due_ = false;
    last_full_ = now;
  }
  std::vector<std::size_t> banks;
  for (std::size_t i = 0; i < states.size() && i < published_.size(); ++i) {
    const bool changed = on_change_ && states[i] != published_[i] && now - published_at_[i] >= min_interval;
    if (!full && !changed) continue;
    banks.push_back(i);
    published_[i] = states[i];
    published_at_[i] = now;
  }
  return banks;
}

}  // namespace unima::mqtt
