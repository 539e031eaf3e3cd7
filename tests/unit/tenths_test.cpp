// Bank A in 0.1 units (seed §6.2.1, SPEC §1): the conversion of a source register's raw
// value into tenths of its unit.

#include <gtest/gtest.h>

#include "banks/table_catalog.hpp"
#include "banks/tenths.hpp"

namespace unima::banks {
namespace {

RegisterDef analog(double scale, bool is_signed) {
  RegisterDef reg;
  reg.kind = RegisterKind::analog;
  reg.scale = scale;
  reg.is_signed = is_signed;
  return reg;
}

std::uint16_t tenths(std::uint16_t raw, const RegisterDef& reg, bool raw_copy = false) {
  return to_tenths(raw, tenths_conversion(&reg, raw_copy));
}

std::uint16_t word(int value) { return static_cast<std::uint16_t>(static_cast<std::int16_t>(value)); }

TEST(Tenths, TheSpecExamples) {
  EXPECT_EQ(tenths(853, analog(0.1, true)), 853);     // oil temperature 85.3 °C: copied
  EXPECT_EQ(tenths(1500, analog(1, false)), 15000);   // speed 1500 min⁻¹: ×10
  EXPECT_EQ(tenths(125, analog(0.01, false)), 13);    // 1.25 bar: ÷10, 12.5 rounds away from zero
  EXPECT_EQ(tenths(124, analog(0.01, false)), 12);
  EXPECT_EQ(tenths(word(-125), analog(0.01, true)), word(-13));
}

TEST(Tenths, HalvesRoundAwayFromZeroExactlyWhateverTheDecimalScale) {
  // 0.78125 % (UIS) and 0.001 A (UVR) are not exact in binary floating point.
  EXPECT_EQ(tenths(2, analog(0.78125, false)), 16);  // 15.625 → 16
  for (int raw = -2000; raw <= 2000; raw += 50) {
    SCOPED_TRACE(raw);
    // raw × 0.001 ÷ 0.1 = raw ÷ 100: every multiple of 50 is a half.
    const int expected = raw / 100 + (raw % 100 == 50 ? 1 : raw % 100 == -50 ? -1 : 0);
    EXPECT_EQ(tenths(word(raw), analog(0.001, true)), word(expected));
  }
}

TEST(Tenths, SignedAndUnsignedReadTheSameBitsDifferently) {
  EXPECT_EQ(tenths(0xFFF6, analog(1, true)), word(-100));  // -10 × 10
  EXPECT_EQ(tenths(0xFFF6, analog(1, false)), 32766);      // 65526 × 10 saturates
}

TEST(Tenths, ResultsSaturateShortOfTheNotMeasuredMarker) {
  EXPECT_EQ(tenths(3277, analog(1, false)), 32766);  // 32770 would be above
  EXPECT_EQ(tenths(3276, analog(1, false)), 32760);
  EXPECT_EQ(tenths(word(-3277), analog(1, true)), word(-32767));
  EXPECT_EQ(tenths(word(-32768), analog(10, true)), word(-32767));
}

TEST(Tenths, NotMeasuredStaysNotMeasured) {
  EXPECT_EQ(tenths(0x7FFF, analog(0.01, false)), 0x7FFF);
  EXPECT_EQ(tenths(0x7FFF, analog(1, true)), 0x7FFF);
}

// SPEC §1: sources in tenths already (W, C, S_N, a 0.1 °C temperature) keep their value,
// and saturate like any result: 0x8000 (−32768) is outside −32767..32766.
TEST(Tenths, SourcesInTenthsAlreadyKeepTheirValueAndSaturate) {
  const auto w = tenths_conversion(nullptr, false);  // W, the source without a table
  EXPECT_EQ(to_tenths(1500, w), 1500);
  EXPECT_EQ(to_tenths(word(-1500), w), word(-1500));
  EXPECT_EQ(to_tenths(0x8000, w), 0x8001);
  EXPECT_EQ(to_tenths(0x8001, w), 0x8001);
  EXPECT_EQ(to_tenths(0x7FFE, w), 0x7FFE);
  EXPECT_EQ(to_tenths(0x7FFF, w), 0x7FFF);  // a master's "not measured" stays so
  EXPECT_EQ(tenths(0x8000, analog(0.1, true)), 0x8001);   // C's user outputs, S_N, temperatures
  EXPECT_EQ(tenths(0x8000, analog(0.1, false)), 32766);   // 3276.8 of an unsigned quantity
  EXPECT_EQ(tenths(853, analog(0.1, false)), 853);
}

TEST(Tenths, RawEntriesAndOtherKindsAreCopied) {
  EXPECT_EQ(tenths(1500, analog(1, false), true), 1500);
  EXPECT_EQ(tenths(0x8000, analog(0.1, true), true), 0x8000);  // raw: true is the register unchanged
  for (auto kind : {RegisterKind::bits, RegisterKind::u32_low, RegisterKind::u32_high, RegisterKind::byte_pair,
                    RegisterKind::ascii_pair}) {
    RegisterDef reg = analog(1, false);
    reg.kind = kind;
    EXPECT_EQ(tenths(0x4142, reg), 0x4142) << kind_name(kind);
  }
}

TEST(Tenths, EveryAnalogRegisterOfTheTablesConvertsWithinRange) {
  for (const auto* table : all_tables())
    for (const auto& reg : table->registers) {
      if (reg.kind != RegisterKind::analog) continue;
      const auto conversion = tenths_conversion(&reg, false);
      EXPECT_EQ(conversion.is_signed, reg.is_signed);
      // The fraction is exact: scale × 10 = numerator ÷ denominator.
      EXPECT_DOUBLE_EQ(reg.scale * 10 * static_cast<double>(conversion.denominator),
                       static_cast<double>(conversion.numerator))
          << table->id << "." << reg.id;
    }
}

}  // namespace
}  // namespace unima::banks
