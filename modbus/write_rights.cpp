#include "modbus/write_rights.hpp"

#include <algorithm>

#include "modbus/protocol.hpp"

namespace unima::modbus {

void WriteRights::allow(std::uint16_t first, std::uint16_t last) {
  if (everything_ || last < first) return;
  ranges_.emplace_back(first, last);
  std::sort(ranges_.begin(), ranges_.end());
  // Merged, so that a write across two listed neighbours (W and X side by side) is one
  // range and allows() needs to look at one range only.
  std::vector<std::pair<std::uint16_t, std::uint16_t>> merged;
  for (const auto& range : ranges_) {
    if (!merged.empty() && range.first <= merged.back().second + 1u)
      merged.back().second = std::max(merged.back().second, range.second);
    else
      merged.push_back(range);
  }
  ranges_ = std::move(merged);
}

void WriteRights::allow_units(std::uint8_t first, std::uint8_t last) {
  for (unsigned unit = first; unit <= last; ++unit) units_[unit] = true;
}

bool WriteRights::may_forward(std::uint8_t unit, std::uint8_t function) const {
  // SPEC §14 lets every client read through the gateway.
  if (function::only_reads(function)) return true;
  return everything_ || units_[unit];
}

bool WriteRights::allows_nothing() const {
  return !everything_ && ranges_.empty() && std::none_of(units_.begin(), units_.end(), [](bool u) { return u; });
}

bool WriteRights::allows(std::uint16_t first, std::uint16_t count) const {
  if (everything_) return true;
  if (count == 0) return false;
  const std::uint32_t last = std::uint32_t{first} + count - 1;
  return std::any_of(ranges_.begin(), ranges_.end(),
                     [&](const auto& range) { return range.first <= first && last <= range.second; });
}

}  // namespace unima::modbus
