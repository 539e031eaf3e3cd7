// The read path of the banks (SPEC §1): what a D_N register reads as its device comes and
// goes on-line and telegrams carry it, and reads that lie in one window, span adjacent
// windows, or touch a gap — in a small space and in the standard layout, write banks
// readable or not, up to the top of the address space.

#include <gtest/gtest.h>

#include <array>
#include <span>
#include <vector>

#include "banks/register_space.hpp"
#include "banks/table_catalog.hpp"
#include "tests/support/bank_layouts.hpp"

namespace unima::banks {
namespace {

using Values = std::vector<std::uint16_t>;

BankShapes shapes_with_chp_in_d1() { return shapes_with({&chp(), nullptr, nullptr, nullptr}); }

Values read(const RegisterStore& store, BankId bank, std::uint16_t offset, std::size_t count) {
  Values out(count);
  store.read(bank, offset, out);
  return out;
}

// unigen-chp: offset 0 holds bits (off-line 0x0000), offsets 1 and 2 an analog value
// (0x7FFF) and the low word of a 32-bit counter (0xFFFF).
const Values offline_d1_0_to_2 = {0x0000, 0x7FFF, 0xFFFF};

TEST(RegisterStore, DeviceBankReadsOfflineValuesUntilOnLineAndCarried) {
  RegisterStore store(shapes_with_chp_in_d1());
  EXPECT_EQ(read(store, BankId::D1, 0, 3), offline_d1_0_to_2);
  EXPECT_TRUE(store.store_telegram(BankId::D1, 1, Values{11}));
  EXPECT_EQ(read(store, BankId::D1, 0, 3), offline_d1_0_to_2);  // carried, but off-line
  store.set_online(BankId::D1, true);
  EXPECT_EQ(read(store, BankId::D1, 0, 3), (Values{0x0000, 11, 0xFFFF}));  // 0 and 2 never carried
  store.store_telegram(BankId::D1, 0, Values{5, 12, 13});
  EXPECT_EQ(read(store, BankId::D1, 0, 3), (Values{5, 12, 13}));
  store.set_online(BankId::D1, false);
  EXPECT_EQ(read(store, BankId::D1, 0, 3), offline_d1_0_to_2);
  store.set_online(BankId::D1, true);  // the values carried before come back
  EXPECT_EQ(read(store, BankId::D1, 0, 3), (Values{5, 12, 13}));
  EXPECT_EQ(store.read(BankId::D1, 1), 12);
}

TEST(RegisterStore, ATelegramPastTheEndIsRefusedWhole) {
  RegisterStore store(shapes_with_chp_in_d1());
  store.set_online(BankId::D1, true);
  const auto before = store.read(BankId::D1, 63);
  EXPECT_FALSE(store.store_telegram(BankId::D1, 63, Values{1, 2, 3}));
  EXPECT_EQ(store.read(BankId::D1, 63), before);  // not even the register inside
  EXPECT_FALSE(store.store_telegram(BankId::D1, 64, Values{1}));
  EXPECT_TRUE(store.store_telegram(BankId::D1, 63, Values{1}));
  EXPECT_EQ(store.read(BankId::D1, 63), 1);
}

TEST(RegisterStore, ReloadCarriesServedValuesOver) {
  RegisterStore old_store(shapes_with_chp_in_d1());
  old_store.set_online(BankId::D1, true);
  old_store.store_telegram(BankId::D1, 1, Values{42});
  RegisterStore new_store(shapes_with_chp_in_d1());
  new_store.take_state_from(old_store);
  EXPECT_EQ(new_store.read(BankId::D1, 1), 42);
  new_store.set_online(BankId::D1, false);
  EXPECT_EQ(new_store.read(BankId::D1, 1), 0x7FFF);
}

class Space : public ::testing::Test {
 protected:
  // D1 (64 registers) at 0x1100, directly followed by W (16) at 0x1140; C at 0x2000.
  static std::vector<Window> windows() {
    return {bank_window(BankId::D1, 0x1100, 64), bank_window(BankId::W, 0x1140, analog_bank_length),
            bank_window(BankId::C, 0x2000, c_bank_length)};
  }
  Values read(std::uint16_t first, std::size_t count, bool* ok = nullptr) const {
    Values out(count, 0xABCD);
    const bool done = space.read(first, out);
    if (ok) *ok = done;
    return done ? out : Values{};
  }

  RegisterStore store{shapes_with_chp_in_d1()};
  RegisterSpace space{AddressMap(windows()), store, AccessRules{}};
};

TEST_F(Space, ReadInsideOneWindow) {
  store.set_online(BankId::D1, true);
  store.store_telegram(BankId::D1, 1, Values{7, 8});
  EXPECT_EQ(read(0x1101, 2), (Values{7, 8}));
  EXPECT_EQ(read(0x1100, 64).size(), 64u);
}

TEST_F(Space, ReadAcrossAdjacentWindows) {
  store.set_online(BankId::D1, true);
  store.store_telegram(BankId::D1, 63, Values{9});
  store.write(BankId::W, 0, 10);
  EXPECT_EQ(read(0x113F, 2), (Values{9, 10}));
}

TEST_F(Space, ReadTouchingAGapOrNothingFails) {
  bool ok = true;
  read(0x1148, 16, &ok);  // W ends at 0x114F; 0x1150 is no register
  EXPECT_FALSE(ok);
  read(0x10FF, 2, &ok);
  EXPECT_FALSE(ok);
  read(0x1100, 0, &ok);
  EXPECT_FALSE(ok);
}

TEST_F(Space, WriteBanksAreUnreadableWhenTheRulesSaySo) {
  RegisterSpace strict(AddressMap(windows()), store, AccessRules{false});
  Values out(1);
  EXPECT_FALSE(strict.read(0x1140, out));
  Values two(2);
  EXPECT_FALSE(strict.read(0x113F, two));
  EXPECT_TRUE(strict.read(0x1100, out));
}

struct SpaceFixture : ::testing::Test {
  SpaceFixture() : store(shapes_with({&chp(), nullptr, nullptr, nullptr})) {}

  AddressMap standard_map() const {
    return AddressMap({bank_window(BankId::A, 0x1000, 16), bank_window(BankId::B, 0x1010, 1),
                       bank_window(BankId::C, 0x1020, 20), bank_window(BankId::D1, 0x1100, 64),
                       bank_window(BankId::S1, 0x2100, 20), bank_window(BankId::W, 0x3000, 16),
                       bank_window(BankId::X, 0x3010, 1)});
  }
  RegisterSpace space(bool readable_write_banks = true) {
    return RegisterSpace(standard_map(), store, AccessRules{readable_write_banks});
  }

  RegisterStore store;
};

TEST_F(SpaceFixture, ReadSpanningTwoAdjacentBanks) {
  auto s = space();
  std::array<std::uint16_t, 2> out = {0xAAAA, 0xAAAA};
  ASSERT_TRUE(s.read(0x100F, out));
  EXPECT_EQ(out[0], 0x7FFF);  // A+15
  EXPECT_EQ(out[1], 0x0000);  // B+0

  store.write(BankId::W, 15, 0x1234);
  store.write(BankId::X, 0, 0x0005);
  ASSERT_TRUE(s.read(0x300F, out));
  EXPECT_EQ(out[0], 0x1234);
  EXPECT_EQ(out[1], 0x0005);

  std::array<std::uint16_t, 17> all{};
  ASSERT_TRUE(s.read(0x1000, all));
  for (std::size_t i = 0; i < 16; ++i) EXPECT_EQ(all[i], 0x7FFF) << i;
  EXPECT_EQ(all[16], 0);
}

TEST_F(SpaceFixture, ReadOfABankInTheMiddle) {
  auto s = space();
  store.set_online(BankId::D1, true);
  const std::vector<std::uint16_t> values = {853, 854};
  store.store_telegram(BankId::D1, 0x21, values);
  std::array<std::uint16_t, 2> out{};
  ASSERT_TRUE(s.read(0x1121, out));
  EXPECT_EQ(out[0], 853);
  EXPECT_EQ(out[1], 854);
  std::array<std::uint16_t, 1> last{};
  ASSERT_TRUE(s.read(0x113F, last));
  EXPECT_EQ(last[0], offline_value(chp().registers[63].kind));
}

TEST_F(SpaceFixture, ReadTouchingAGapFails) {
  auto s = space();
  std::array<std::uint16_t, 2> two{};
  std::array<std::uint16_t, 1> one{};
  EXPECT_FALSE(s.read(0x1033, two));   // C+0x13 then the gap at 0x1034
  EXPECT_FALSE(s.read(0x1010, two));   // B then the gap at 0x1011
  EXPECT_FALSE(s.read(0x0FFF, two));   // the gap before A
  EXPECT_FALSE(s.read(0x1034, one));
  EXPECT_FALSE(s.read(0x1140, one));   // just past D1
  EXPECT_FALSE(s.read(0x1200, one));   // D2 does not exist
  EXPECT_TRUE(s.read(0x1033, one));
  EXPECT_TRUE(s.read(0x113F, one));
  std::array<std::uint16_t, 64> d1{};
  EXPECT_TRUE(s.read(0x1100, d1));
  std::array<std::uint16_t, 65> past_d1{};
  EXPECT_FALSE(s.read(0x1100, past_d1));
}

TEST_F(SpaceFixture, ReadingTheWriteBanksFollowsTheRule) {
  store.write(BankId::W, 0, 99);
  std::array<std::uint16_t, 1> out{};
  {
    auto s = space(false);
    EXPECT_FALSE(s.read(0x3000, out));
    EXPECT_FALSE(s.read(0x3010, out));
    std::array<std::uint16_t, 2> span{};
    EXPECT_FALSE(s.read(0x300F, span));
    EXPECT_TRUE(s.read(0x1000, out));  // other banks are still readable
  }
  {
    auto s = space(true);
    ASSERT_TRUE(s.read(0x3000, out));
    EXPECT_EQ(out[0], 99);
    ASSERT_TRUE(s.read(0x3010, out));
    EXPECT_EQ(out[0], 0);
  }
}

TEST_F(SpaceFixture, ReadOfCountZeroFails) {
  auto s = space();
  std::span<std::uint16_t> no_out;
  EXPECT_FALSE(s.read(0x1000, no_out));
}

TEST(RegisterSpace, RangesRunningPastTheTopOfTheAddressSpaceFail) {
  RegisterStore store(shapes_with({nullptr, nullptr, nullptr, nullptr}));
  RegisterSpace s(AddressMap({bank_window(BankId::W, 0xFFF0, 16)}), store, AccessRules{});
  std::array<std::uint16_t, 16> sixteen{};
  EXPECT_TRUE(s.read(0xFFF0, sixteen));
  std::array<std::uint16_t, 2> two{};
  EXPECT_FALSE(s.read(0xFFFF, two));
}

}  // namespace
}  // namespace unima::banks
