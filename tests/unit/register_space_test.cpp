// The read path of the banks (SPEC §1): what a D_N register reads as its device comes and
// goes on-line and telegrams carry it, and reads that lie in one window, span adjacent
// windows, or touch a gap.

#include <gtest/gtest.h>

#include <vector>

#include "banks/register_space.hpp"
#include "banks/table_catalog.hpp"

namespace unima::banks {
namespace {

using Values = std::vector<std::uint16_t>;

BankShapes shapes_with_chp_in_d1() {
  return standard_shapes({find_device_type("unigen-chp"), nullptr, nullptr, nullptr}, io_module_table(),
                         bridge_internal_table());
}

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
  static Window bank_window(BankId bank, std::uint16_t first, std::uint16_t count) {
    Window w;
    w.bank = bank;
    w.first = first;
    w.count = count;
    w.name = std::string("bank ") + std::string(bank_name(bank));
    return w;
  }
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

}  // namespace
}  // namespace unima::banks
