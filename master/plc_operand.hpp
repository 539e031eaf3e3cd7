#pragma once
// PLC operands as a PLC's own manual writes them (WECON LX5V, seed 003): `X17` and `Y10`
// numbered in octal, `M100`, `D200` in decimal, each one cell of a Modbus table at its
// class's offset (the profile's `operands`). Pure.

#include <cstdint>
#include <string>
#include <string_view>
#include <variant>

#include "master/device_profile.hpp"

namespace unima::master {

struct ResolvedOperand {
  const OperandClass* operand_class = nullptr;
  unsigned number = 0;    // the operand's number (15 for X17)
  std::uint16_t reg = 0;  // its Modbus address in the class's table
};

/// `text` ("D200", "x17": letters in any case) as the profile's classes map it, or why it
/// is not one of them: an unknown class, a digit the class's numbering does not have, a
/// number outside the class's range.
std::variant<ResolvedOperand, std::string> resolve_operand(const DeviceProfile& profile, std::string_view text);

}  // namespace unima::master
