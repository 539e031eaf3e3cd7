#include "banks/bank_id.hpp"

namespace unima::banks {

namespace {
constexpr std::array<std::string_view, bank_count> names = {
    "A", "B", "C", "D1", "D2", "D3", "D4", "S1", "S2", "S3", "S4", "S5", "S6", "S7", "W", "X"};
}

std::string_view bank_name(BankId bank) { return names[index_of(bank)]; }

std::optional<BankId> parse_bank_name(std::string_view name) {
  for (BankId bank : all_banks)
    if (names[index_of(bank)] == name) return bank;
  return std::nullopt;
}

std::uint16_t default_base(BankId bank) {
  switch (bank) {
    case BankId::A: return 0x1000;
    case BankId::B: return 0x1010;
    case BankId::C: return 0x1020;
    case BankId::W: return 0x3000;
    case BankId::X: return 0x3010;
    default: break;
  }
  if (is_device_bank(bank)) return static_cast<std::uint16_t>(0x1100 + 0x100 * (bank_number(bank) - 1));
  return static_cast<std::uint16_t>(0x2100 + 0x100 * (bank_number(bank) - 1));
}

}  // namespace unima::banks
