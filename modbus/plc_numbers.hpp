#pragma once
// The PLC-style register numbers (Modicon's convention) that SCADA packages and PLC manuals
// use besides the 0-based protocol address: 3xxxx for an input register (function 4),
// 4xxxx for a holding register (functions 3, 6, 16), counted from 1 — address 0x0000 is
// 30001 / 40001. Five digits reach address 9998 only; the six-digit form (300001 /
// 400001 + address) reaches every address. `unima-bridge map` prints them, and the config
// warns when a register key holds one, as a PLC habit would write it.

#include <cstdint>
#include <optional>

namespace unima::modbus {

enum class PlcTable { input, holding };  // 3xxxx, 4xxxx
enum class PlcDigits { five, six };

/// The highest address the five-digit form can number (39999 / 49999).
inline constexpr std::uint16_t highest_five_digit_address = 9998;

/// 30001 + address, 400001 + address, …; `digits` five needs address <= 9998.
unsigned plc_number(PlcTable table, std::uint16_t address, PlcDigits digits);

/// The one form for a set of addresses whose highest is `highest`: five digits while they
/// all fit, else six for all (a column of numbers never mixes the two).
PlcDigits plc_digits_for(std::uint16_t highest);

struct PlcRegister {
  PlcTable table;
  std::uint16_t address;  // the protocol's 0-based address it means
  PlcDigits digits;
};

/// What `number` means read as a PLC-style number: 30001..39999, 40001..49999,
/// 300001..365536, 400001..465536; nullopt for any other number.
std::optional<PlcRegister> read_plc_number(unsigned long number);

}  // namespace unima::modbus
