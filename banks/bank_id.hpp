#pragma once
// The register banks of the Bridge (seed 004 §6.1, SPEC §1).

#include <array>
#include <cstdint>
#include <optional>
#include <string_view>

namespace unima::banks {

enum class BankId : std::uint8_t { A, B, C, D1, D2, D3, D4, S1, S2, S3, S4, S5, S6, S7, W, X };

inline constexpr std::size_t bank_count = 16;

inline constexpr std::array<BankId, bank_count> all_banks = {
    BankId::A,  BankId::B,  BankId::C,  BankId::D1, BankId::D2, BankId::D3, BankId::D4, BankId::S1,
    BankId::S2, BankId::S3, BankId::S4, BankId::S5, BankId::S6, BankId::S7, BankId::W,  BankId::X};

constexpr std::size_t index_of(BankId bank) { return static_cast<std::size_t>(bank); }

/// "A", "D3", "S7", ... as written in configs and in the monitor.
std::string_view bank_name(BankId bank);
std::optional<BankId> parse_bank_name(std::string_view name);

/// The seed's default base address (seed 004 §6.1).
std::uint16_t default_base(BankId bank);

/// Register count of each bank (SPEC §1).
inline constexpr std::uint16_t analog_bank_length = 16;  // A, W
inline constexpr std::uint16_t bit_bank_length = 1;      // B, X
inline constexpr std::uint16_t c_bank_length = 20;       // C+0x00..+0x13
inline constexpr std::uint16_t s_bank_length = 20;       // S_N
/// A D_N is the seed's window 0x1100÷0x113F whatever its device type (seed 004 §6.1), so
/// that a SCADA template written for the hardware reads it whole; past its table's end
/// it reads 0x7FFF, like a reserve.
inline constexpr std::uint16_t device_bank_length = 64;
/// A device table fills at most its bank's window.
inline constexpr std::uint16_t max_table_length = device_bank_length;

constexpr bool is_device_bank(BankId bank) { return bank >= BankId::D1 && bank <= BankId::D4; }
constexpr bool is_module_bank(BankId bank) { return bank >= BankId::S1 && bank <= BankId::S7; }
/// W and X are the banks the Modbus master writes into (seed §6.2.6, §6.2.7).
constexpr bool is_write_bank(BankId bank) { return bank == BankId::W || bank == BankId::X; }

/// 1 for D1 or S1, 4 for D4, 7 for S7.
constexpr unsigned bank_number(BankId bank) {
  if (is_device_bank(bank)) return index_of(bank) - index_of(BankId::D1) + 1;
  if (is_module_bank(bank)) return index_of(bank) - index_of(BankId::S1) + 1;
  return 0;
}
constexpr BankId device_bank(unsigned n) { return static_cast<BankId>(index_of(BankId::D1) + n - 1); }
constexpr BankId module_bank(unsigned n) { return static_cast<BankId>(index_of(BankId::S1) + n - 1); }

/// 0x7FFF in an analog register means "not measured" (seed §5.1).
inline constexpr std::uint16_t not_measured = 0x7FFF;

}  // namespace unima::banks
