#include "mqtt/bank_documents.hpp"

#include <algorithm>
#include <cmath>

#include "monitor/monitor_line.hpp"

namespace unima::mqtt {

namespace {

constexpr std::uint16_t not_measured = 0x7FFF;

bool published_bank(const std::string& bank) {
  if (bank == "A" || bank == "B" || bank == "C") return true;
  return bank.size() == 2 && (bank[0] == 'D' || bank[0] == 'S') && bank[1] >= '1' && bank[1] <= '7';
}

// Keeps a scaled value's decimals to the scale's own (0.1 -> one), not binary noise.
double rounded(double value, double scale) {
  if (scale >= 1) return value;
  const double digits = std::pow(10.0, std::ceil(-std::log10(scale) - 1e-9));
  return std::round(value * digits) / digits;
}

}  // namespace

std::vector<BankLayout> bank_layouts(const std::vector<config::MapRow>& rows, const banks::Mapping& mapping) {
  std::vector<BankLayout> layouts;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const auto& row = rows[i];
    if (!published_bank(row.bank)) continue;
    if (layouts.empty() || layouts.back().bank != row.bank) layouts.push_back({row.bank, {}});
    auto& registers = layouts.back().registers;
    if (row.bank == "A" && row.offset < mapping.analog.size() && mapping.analog[row.offset]) {
      registers.push_back({mapping.analog[row.offset]->text, row.kind, row.scale, i, std::nullopt});
      continue;
    }
    if (row.bank == "B" && std::any_of(mapping.bits.begin(), mapping.bits.end(), [](const auto& b) { return b.has_value(); })) {
      for (unsigned bit = 0; bit < mapping.bits.size(); ++bit)
        if (mapping.bits[bit]) registers.push_back({mapping.bits[bit]->text, "bit", 1.0, i, bit});
      continue;
    }
    registers.push_back({row.id, row.kind, row.scale, i, std::nullopt});
  }
  return layouts;
}

nlohmann::json engineering_value(const BankRegister& reg, std::optional<std::uint16_t> raw) {
  if (!raw) return nullptr;
  if (reg.bit) return (*raw >> *reg.bit) & 1u;
  if (reg.kind == "analog") {
    if (*raw == not_measured) return nullptr;
    const auto signed_value = static_cast<std::int16_t>(*raw);
    if (reg.scale == 1.0) return signed_value;
    return rounded(signed_value * reg.scale, reg.scale);
  }
  if (reg.scale == 1.0) return *raw;
  return rounded(*raw * reg.scale, reg.scale);
}

nlohmann::ordered_json bank_document(const BankLayout& layout, std::span<const std::optional<std::uint16_t>> values, bool online,
                             std::chrono::system_clock::time_point now) {
  nlohmann::ordered_json document = nlohmann::ordered_json::object();  // time, online, then the table's order
  std::string time;
  monitor::append_utc_time(time, now);
  document["time"] = time;
  document["online"] = online;
  for (const auto& reg : layout.registers) document[reg.key] = engineering_value(reg, values[reg.row]);
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
