// Bank ids (SPEC §1): their default bases, names, numbers and kinds.

#include <gtest/gtest.h>

#include <string>
#include <string_view>

#include "banks/bank_id.hpp"

namespace unima::banks {
namespace {

TEST(BankId, DefaultBasesFollowTheSeed) {
  EXPECT_EQ(default_base(BankId::A), 0x1000);
  EXPECT_EQ(default_base(BankId::B), 0x1010);
  EXPECT_EQ(default_base(BankId::C), 0x1020);
  EXPECT_EQ(default_base(BankId::D1), 0x1100);
  EXPECT_EQ(default_base(BankId::D2), 0x1200);
  EXPECT_EQ(default_base(BankId::D3), 0x1300);
  EXPECT_EQ(default_base(BankId::D4), 0x1400);
  EXPECT_EQ(default_base(BankId::S1), 0x2100);
  EXPECT_EQ(default_base(BankId::S2), 0x2200);
  EXPECT_EQ(default_base(BankId::S3), 0x2300);
  EXPECT_EQ(default_base(BankId::S4), 0x2400);
  EXPECT_EQ(default_base(BankId::S5), 0x2500);
  EXPECT_EQ(default_base(BankId::S6), 0x2600);
  EXPECT_EQ(default_base(BankId::S7), 0x2700);
  EXPECT_EQ(default_base(BankId::W), 0x3000);
  EXPECT_EQ(default_base(BankId::X), 0x3010);
}

TEST(BankId, NamesRoundTrip) {
  const std::array<std::string_view, bank_count> expected = {"A",  "B",  "C",  "D1", "D2", "D3", "D4", "S1",
                                                            "S2", "S3", "S4", "S5", "S6", "S7", "W",  "X"};
  for (std::size_t i = 0; i < bank_count; ++i) {
    const BankId bank = all_banks[i];
    EXPECT_EQ(index_of(bank), i);
    EXPECT_EQ(bank_name(bank), expected[i]);
    const auto parsed = parse_bank_name(bank_name(bank));
    ASSERT_TRUE(parsed.has_value()) << expected[i];
    EXPECT_EQ(*parsed, bank);
  }
}

TEST(BankId, UnknownNamesAreRejected) {
  for (std::string_view name : {"", "D", "D0", "D5", "S0", "S8", "d1", "a", "w", "AA", "Y", "C1", " A", "A "})
    EXPECT_FALSE(parse_bank_name(name).has_value()) << "'" << name << "'";
}

TEST(BankId, NumbersAndKinds) {
  EXPECT_EQ(bank_number(BankId::D1), 1u);
  EXPECT_EQ(bank_number(BankId::D4), 4u);
  EXPECT_EQ(bank_number(BankId::S1), 1u);
  EXPECT_EQ(bank_number(BankId::S7), 7u);
  EXPECT_EQ(bank_number(BankId::W), 0u);
  for (unsigned n = 1; n <= 4; ++n) EXPECT_EQ(bank_number(device_bank(n)), n);
  for (unsigned n = 1; n <= 7; ++n) EXPECT_EQ(bank_number(module_bank(n)), n);
  EXPECT_TRUE(is_device_bank(BankId::D3));
  EXPECT_FALSE(is_device_bank(BankId::S1));
  EXPECT_TRUE(is_module_bank(BankId::S7));
  EXPECT_FALSE(is_module_bank(BankId::D4));
  EXPECT_TRUE(is_write_bank(BankId::W));
  EXPECT_TRUE(is_write_bank(BankId::X));
  EXPECT_FALSE(is_write_bank(BankId::C));
}

}  // namespace
}  // namespace unima::banks
