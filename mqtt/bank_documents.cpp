#include "mqtt/bank_documents.hpp"

#include "platform/utc_time.hpp"
#include "values/value_json.hpp"

namespace unima::mqtt {

std::vector<banks::BankId> published_banks(const values::ValueModel& model) {
  std::vector<banks::BankId> banks;
  for (const auto& layout : model.banks())
    if (!banks::is_write_bank(layout.bank)) banks.push_back(layout.bank);
  return banks;
}

nlohmann::ordered_json bank_document(const values::BankValues& layout, std::span<const values::Value> values, bool online,
                                     std::chrono::system_clock::time_point measured) {
  std::string time;
  platform::append_utc_time(time, measured);
  nlohmann::ordered_json document = {{"time", time}, {"online", online}};
  for (std::size_t i = 0; i < layout.values.size() && i < values.size(); ++i)
    if (values::published(values[i])) document[layout.values[i].name] = values::reading_json(layout.values[i], values[i]);
  return document;
}

}  // namespace unima::mqtt
