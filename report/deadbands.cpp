#include "report/deadbands.hpp"

#include <algorithm>

#include <fmt/format.h>

namespace unima::report {

namespace {

// The index of the value named `name` in `layout`; nullopt when it has none.
std::optional<std::size_t> index_of_value(const values::BankValues* layout, std::string_view name) {
  if (!layout) return std::nullopt;
  const auto found = std::find_if(layout->values.begin(), layout->values.end(),
                                  [&](const values::ValueDef& def) { return def.name == name; });
  if (found == layout->values.end()) return std::nullopt;
  return static_cast<std::size_t>(found - layout->values.begin());
}

}  // namespace

bool takes_deadband(const values::ValueDef& def) {
  return def.type == values::ValueType::number && def.decoding != values::Decoding::word &&
         def.decoding != values::Decoding::bit_field;
}

Deadbands::Deadbands(const config::ReportConfig& report, const values::ValueModel& model) {
  for (const auto& layout : model.banks()) {
    auto& deadbands = banks_[banks::index_of(layout.bank)];
    deadbands.reserve(layout.values.size());
    for (const auto& def : layout.values) deadbands.push_back(takes_deadband(def) ? report.default_deadband : 0);
  }
  for (const auto& entry : report.deadbands) {
    const auto* layout = model.bank(entry.bank);
    const auto key = fmt::format("report.deadband.{}.{}", banks::bank_name(entry.bank), entry.value);
    const auto index = index_of_value(layout, entry.value);
    if (!index)
      throw config::ConfigError(fmt::format("{}: {}: {} has no value {} (`unima-bridge map` lists them)", entry.origin, key,
                                            banks::bank_name(entry.bank), entry.value));
    const auto& def = layout->values[*index];
    if (!takes_deadband(def))
      throw config::ConfigError(fmt::format("{}: {}: {} is a {}, whose every change counts; a deadband is for numbers",
                                            entry.origin, key, entry.value,
                                            def.type == values::ValueType::text ? "text" : "bit or bit word"));
    banks_[banks::index_of(entry.bank)][*index] = entry.deadband;
  }
}

}  // namespace unima::report
