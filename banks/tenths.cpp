#include "banks/tenths.hpp"

#include <cmath>

#include "banks/bank_id.hpp"

namespace unima::banks {

namespace {

constexpr std::int64_t lowest_tenths = -32767;  // -32768 (0x8000) is left out for symmetry
constexpr std::int64_t highest_tenths = 32766;  // 32767 (0x7FFF) means "not measured"

// A / B rounded half away from zero; B > 0.
std::int64_t divide_rounded(std::int64_t a, std::int64_t b) {
  const std::int64_t magnitude = (2 * (a < 0 ? -a : a) + b) / (2 * b);
  return a < 0 ? -magnitude : magnitude;
}

}  // namespace

TenthsConversion tenths_conversion(const RegisterDef* source, bool raw) {
  TenthsConversion conversion;
  if (raw) return conversion;
  if (!source) return {.copy = false, .is_signed = true};  // W: tenths a master wrote, -32768..32767
  if (source->kind != RegisterKind::analog) return conversion;
  conversion.copy = false;
  const double factor = source->scale * 10.0;
  // The smallest power of ten that makes the factor whole (scales have at most 7 decimals).
  std::int64_t denominator = 1;
  while (denominator < 10'000'000 && std::abs(factor * static_cast<double>(denominator) -
                                             std::round(factor * static_cast<double>(denominator))) > 1e-6)
    denominator *= 10;
  const auto numerator = static_cast<std::int64_t>(std::llround(factor * static_cast<double>(denominator)));
  conversion.is_signed = source->is_signed;
  if (numerator == denominator) return conversion;  // already in tenths
  conversion.numerator = numerator;
  conversion.denominator = denominator;
  return conversion;
}

std::uint16_t to_tenths(std::uint16_t raw, const TenthsConversion& conversion) {
  if (conversion.copy || raw == not_measured) return raw;
  const std::int64_t value = conversion.is_signed ? static_cast<std::int16_t>(raw) : raw;
  std::int64_t tenths = divide_rounded(value * conversion.numerator, conversion.denominator);
  if (tenths < lowest_tenths) tenths = lowest_tenths;
  if (tenths > highest_tenths) tenths = highest_tenths;
  return static_cast<std::uint16_t>(static_cast<std::int16_t>(tenths));
}

}  // namespace unima::banks
