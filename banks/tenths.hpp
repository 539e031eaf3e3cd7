#pragma once
// Bank A shows each mapped quantity in 0.1 of its unit (seed §6.2.1, SPEC §1):
// A = round(raw × scale ÷ 0.1), signed where the source's table says so, rounded half away
// from zero and saturated to −32767..32766, so that 0x7FFF keeps meaning "not measured".

#include <cstdint>

#include "banks/device_table.hpp"

namespace unima::banks {

/// How one entry of bank A turns its source's raw value into tenths.
struct TenthsConversion {
  bool copy = true;        // not a quantity (raw: true, bits, text, 32-bit halves): copied
  bool is_signed = false;  // the raw value is two's complement
  // raw × scale ÷ 0.1 as the exact fraction raw × numerator ÷ denominator (1/1 for a source
  // in tenths already): the tables' scales are decimal (0.01, 0.78125, 0.097656), and
  // floating point would round 2.5 down.
  std::int64_t numerator = 1;
  std::int64_t denominator = 1;
};

/// The conversion for a source register; `source` is nullptr for banks without a table
/// (W: signed tenths) and `raw` is the mapping's `raw: true`. A source in tenths already
/// (scale 0.1: W, C, S_N, temperatures) keeps its value but saturates like any result
/// (0x8000, −32768, reads −32767); `raw: true` entries and registers that are not analog
/// are copied.
TenthsConversion tenths_conversion(const RegisterDef* source, bool raw);

/// The value bank A reads for a measured source value `raw`. A source that reads 0x7FFF
/// itself is not measured, and so is the result.
std::uint16_t to_tenths(std::uint16_t raw, const TenthsConversion& conversion);

}  // namespace unima::banks
