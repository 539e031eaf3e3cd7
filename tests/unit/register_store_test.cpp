// The register store (SPEC §1): the shapes of the banks, what a device's registers read on
// and off line, the fixed banks, writes and their listener, the online bits, and the state
// a reload carries over.

#include <gtest/gtest.h>

#include <array>
#include <stdexcept>
#include <vector>

#include "banks/register_store.hpp"
#include "banks/table_catalog.hpp"
#include "tests/support/bank_layouts.hpp"

namespace unima::banks {
namespace {

std::uint16_t first_offset_of_kind(const DeviceTable& table, RegisterKind kind) {
  for (const auto& r : table.registers)
    if (r.kind == kind) return r.offset;
  throw std::runtime_error("no register of that kind");
}

TEST(RegisterStore, ShapesOfTheBanks) {
  const RegisterStore store(shapes_with({&chp(), nullptr, find_device_type("usc"), nullptr}));
  EXPECT_EQ(store.length(BankId::A), 16);
  EXPECT_EQ(store.length(BankId::B), 1);
  EXPECT_EQ(store.length(BankId::C), 20);
  EXPECT_EQ(store.length(BankId::W), 16);
  EXPECT_EQ(store.length(BankId::X), 1);
  for (unsigned n = 1; n <= 7; ++n) EXPECT_EQ(store.length(module_bank(n)), 20);
  EXPECT_EQ(store.length(BankId::D1), 64);
  EXPECT_TRUE(store.exists(BankId::D1));
  EXPECT_FALSE(store.exists(BankId::D2));
  // A D_N is the seed's window of 64 whatever its type (seed §6.1); the USC's table fills 40.
  EXPECT_EQ(store.length(BankId::D3), 64);
  EXPECT_EQ(store.filled_length(BankId::D3), 0x28);
  EXPECT_EQ(store.filled_length(BankId::D1), 64);
  EXPECT_FALSE(store.exists(BankId::D4));
  EXPECT_EQ(store.table(BankId::D1), &chp());
  EXPECT_EQ(store.table(BankId::D2), nullptr);
}

TEST(RegisterStore, OfflineDeviceReadsOfflineValuesEvenAfterATelegram) {
  RegisterStore store(shapes_with({&chp(), nullptr, nullptr, nullptr}));
  const auto& table = chp();
  auto expect_all_offline = [&] {
    for (const auto& r : table.registers)
      EXPECT_EQ(store.read(BankId::D1, r.offset), offline_value(r.kind)) << r.id;
  };
  expect_all_offline();
  std::vector<std::uint16_t> values(table.length());
  for (std::size_t i = 0; i < values.size(); ++i) values[i] = static_cast<std::uint16_t>(0x0100 + i);
  EXPECT_TRUE(store.store_telegram(BankId::D1, 0, values));
  EXPECT_FALSE(store.online(BankId::D1));
  expect_all_offline();
  // On-line, the same registers show what the telegram carried.
  store.set_online(BankId::D1, true);
  for (std::size_t i = 0; i < values.size(); ++i) EXPECT_EQ(store.read(BankId::D1, static_cast<std::uint16_t>(i)), values[i]);
  // Off-line again: back to the off-line values.
  store.set_online(BankId::D1, false);
  expect_all_offline();
}

TEST(RegisterStore, OnlineDeviceReadsOnlyTheRegistersATelegramCarried) {
  RegisterStore store(shapes_with({&chp(), nullptr, nullptr, nullptr}));
  const auto& table = chp();
  store.set_online(BankId::D1, true);
  const std::vector<std::uint16_t> values = {853, 854};
  EXPECT_TRUE(store.store_telegram(BankId::D1, 0x21, values));
  EXPECT_EQ(store.read(BankId::D1, 0x21), 853);
  EXPECT_EQ(store.read(BankId::D1, 0x22), 854);
  for (const auto& r : table.registers) {
    if (r.offset == 0x21 || r.offset == 0x22) continue;
    EXPECT_EQ(store.read(BankId::D1, r.offset), offline_value(r.kind)) << r.id;
  }
  // A bit register not yet carried reads 0; an analog one 0x7FFF.
  EXPECT_EQ(store.read(BankId::D1, first_offset_of_kind(table, RegisterKind::bits)), 0);
  EXPECT_EQ(store.read(BankId::D1, first_offset_of_kind(table, RegisterKind::analog)), 0x7FFF);
  // The span read agrees with single reads.
  std::array<std::uint16_t, 4> out{};
  store.read(BankId::D1, 0x20, out);
  EXPECT_EQ(out[0], offline_value(table.registers[0x20].kind));
  EXPECT_EQ(out[1], 853);
  EXPECT_EQ(out[2], 854);
  EXPECT_EQ(out[3], offline_value(table.registers[0x23].kind));
}

TEST(RegisterStore, BitRegistersReadZeroOffline) {
  RegisterStore store(shapes_with({&chp(), nullptr, nullptr, nullptr}));
  const auto bits = first_offset_of_kind(chp(), RegisterKind::bits);
  const std::vector<std::uint16_t> v = {0xFFFF};
  store.store_telegram(BankId::D1, bits, v);
  EXPECT_EQ(store.read(BankId::D1, bits), 0);
  store.set_online(BankId::D1, true);
  EXPECT_EQ(store.read(BankId::D1, bits), 0xFFFF);
  store.set_online(BankId::D1, false);
  EXPECT_EQ(store.read(BankId::D1, bits), 0);
}

TEST(RegisterStore, ATelegramRunningPastTheEndStoresNothing) {
  RegisterStore store(shapes_with({&chp(), nullptr, nullptr, nullptr}));
  store.set_online(BankId::D1, true);
  const std::vector<std::uint16_t> values = {1, 2, 3};
  const auto before = std::array{store.read(BankId::D1, 62), store.read(BankId::D1, 63)};
  EXPECT_FALSE(store.store_telegram(BankId::D1, 62, values));  // 62, 63, and one past the end
  EXPECT_EQ((std::array{store.read(BankId::D1, 62), store.read(BankId::D1, 63)}), before);
  EXPECT_FALSE(store.store_telegram(BankId::D1, 64, values));
  EXPECT_FALSE(store.store_telegram(BankId::D2, 0, values));  // no D2 configured
}

// Past a table's end a D_N reads 0x7FFF, on-line or not, whatever a telegram says: the
// telegram that reaches there is refused whole.
TEST(RegisterStore, ADeviceBankPastItsTableReadsNotMeasured) {
  const auto* usc = find_device_type("usc");
  RegisterStore store(shapes_with({usc, nullptr, nullptr, nullptr}));
  store.set_online(BankId::D1, true);
  const std::vector<std::uint16_t> table_values(usc->length(), 1234);
  EXPECT_TRUE(store.store_telegram(BankId::D1, 0, table_values));
  EXPECT_FALSE(store.store_telegram(BankId::D1, usc->length() - 1, std::vector<std::uint16_t>{1, 2}));
  EXPECT_FALSE(store.store_telegram(BankId::D1, usc->length(), std::vector<std::uint16_t>{1}));
  std::vector<std::uint16_t> window(device_bank_length);
  store.read(BankId::D1, 0, window);
  for (std::uint16_t offset = 0; offset < device_bank_length; ++offset) {
    EXPECT_EQ(window[offset], offset < usc->length() ? 1234 : not_measured) << offset;
    EXPECT_EQ(store.measured(BankId::D1, offset), offset < usc->length()) << offset;
  }
}

TEST(RegisterStore, ModuleBanks) {
  RegisterStore store(shapes_with({nullptr, nullptr, nullptr, nullptr}));
  const DeviceTable& io = *io_module_table();
  for (const auto& r : io.registers) EXPECT_EQ(store.read(BankId::S3, r.offset), offline_value(r.kind)) << r.id;
  const std::vector<std::uint16_t> values = {11, 12};
  store.store_telegram(BankId::S3, 0, values);
  EXPECT_EQ(store.read(BankId::S3, 0), offline_value(io.registers[0].kind));
  store.set_online(BankId::S3, true);
  EXPECT_EQ(store.read(BankId::S3, 0), 11);
  EXPECT_EQ(store.read(BankId::S3, 1), 12);
  EXPECT_EQ(store.read(BankId::S4, 0), offline_value(io.registers[0].kind));
}

TEST(RegisterStore, InitialValuesOfTheFixedBanks) {
  const RegisterStore store(shapes_with({nullptr, nullptr, nullptr, nullptr}));
  for (std::uint16_t i = 0; i < 16; ++i) {
    EXPECT_EQ(store.read(BankId::W, i), 0x7FFF) << i;
    EXPECT_EQ(store.read(BankId::A, i), 0x7FFF) << i;
    EXPECT_EQ(store.read(BankId::C, i), 0x7FFF) << i;  // user analog outputs not yet set
  }
  EXPECT_EQ(store.read(BankId::X, 0), 0);
  EXPECT_EQ(store.read(BankId::B, 0), 0);
  EXPECT_EQ(store.read(BankId::C, c_bank::user_binary_inputs), 0);
  EXPECT_EQ(store.read(BankId::C, c_bank::user_binary_outputs), 0);
  EXPECT_EQ(store.read(BankId::C, c_bank::online_bits), 0);
}

struct Change {
  BankId bank;
  std::uint16_t offset;
  std::uint16_t value;
  bool operator==(const Change&) const = default;
};

TEST(RegisterStore, WriteNotifiesTheListener) {
  RegisterStore store(shapes_with({nullptr, nullptr, nullptr, nullptr}));
  std::vector<Change> changes;
  store.set_change_listener([&](BankId b, std::uint16_t o, std::uint16_t v) { changes.push_back({b, o, v}); });
  store.write(BankId::W, 3, 1234);
  store.write(BankId::X, 0, 0x0005);
  EXPECT_EQ(store.read(BankId::W, 3), 1234);
  EXPECT_EQ(store.read(BankId::W, 2), 0x7FFF);
  EXPECT_EQ(store.read(BankId::X, 0), 5);
  const std::vector<Change> expected = {{BankId::W, 3, 1234}, {BankId::X, 0, 5}};
  EXPECT_EQ(changes, expected);
}

// Who publishes northbound hears of every change a read would see, and of nothing else.
TEST(RegisterStore, UserOutputNIsCPlusNMinusOne) {
  RegisterStore store(shapes_with({nullptr, nullptr, nullptr, nullptr}));
  std::vector<Change> changes;
  store.set_change_listener([&](BankId b, std::uint16_t o, std::uint16_t v) { changes.push_back({b, o, v}); });
  store.set_user_output(1, 100);
  store.set_user_output(3, 300);
  store.set_user_output(16, 1600);
  EXPECT_EQ(store.read(BankId::C, 0), 100);
  EXPECT_EQ(store.read(BankId::C, 1), 0x7FFF);
  EXPECT_EQ(store.read(BankId::C, 2), 300);
  EXPECT_EQ(store.read(BankId::C, 15), 1600);
  EXPECT_EQ(store.read(BankId::C, 0x10), 0);  // not spilled into the user binary inputs
  const std::vector<Change> expected = {{BankId::C, 0, 100}, {BankId::C, 2, 300}, {BankId::C, 15, 1600}};
  EXPECT_EQ(changes, expected);
}

TEST(RegisterStore, OnlineBits) {
  RegisterStore store(shapes_with({&chp(), &chp(), &chp(), &chp()}));
  EXPECT_EQ(store.online_bits(), 0);
  for (unsigned n = 1; n <= 4; ++n) {
    store.set_online(device_bank(n), true);
    EXPECT_EQ(store.online_bits(), 1u << (n - 1)) << "D" << n;
    EXPECT_EQ(store.read(BankId::C, c_bank::online_bits), 1u << (n - 1)) << "D" << n;
    store.set_online(device_bank(n), false);
  }
  for (unsigned n = 1; n <= 7; ++n) {
    store.set_online(module_bank(n), true);
    EXPECT_EQ(store.online_bits(), 1u << (7 + n)) << "S" << n;
    EXPECT_EQ(store.read(BankId::C, c_bank::online_bits), 1u << (7 + n)) << "S" << n;
    store.set_online(module_bank(n), false);
  }
  store.set_modbus_error(true);
  EXPECT_EQ(store.online_bits(), 0x8000);
  EXPECT_EQ(store.read(BankId::C, 0x13), 0x8000);
  store.set_modbus_error(false);
  EXPECT_EQ(store.read(BankId::C, 0x13), 0);

  store.set_online(BankId::D1, true);
  store.set_online(BankId::D3, true);
  store.set_online(BankId::S2, true);
  store.set_online(BankId::S7, true);
  store.set_modbus_error(true);
  EXPECT_EQ(store.read(BankId::C, 0x13), 0x0001 | 0x0004 | 0x0200 | 0x4000 | 0x8000);
  // Read as part of a span of C too.
  std::array<std::uint16_t, 2> out{};
  store.read(BankId::C, 0x12, out);
  EXPECT_EQ(out[1], 0xC205);
}

// What senders north compare (SPEC §12's leading edge): a count per bank that moves when
// what the bank shows does, and a signal once per arming.
TEST(RegisterStore, ChangeCountsMoveWithWhatTheBankShows) {
  RegisterStore store(shapes_with({&chp(), nullptr, nullptr, nullptr}));
  const std::array<std::uint16_t, 2> values{7, 8};
  const auto d1 = store.changes(BankId::D1);
  const auto c = store.changes(BankId::C);
  const auto s1 = store.changes(BankId::S1);
  ASSERT_TRUE(store.store_telegram(BankId::D1, 0, values));
  EXPECT_EQ(store.changes(BankId::D1), d1 + 1);
  EXPECT_EQ(store.changes(BankId::S1), s1) << "another bank";
  ASSERT_TRUE(store.store_telegram(BankId::D1, 0, values));
  EXPECT_EQ(store.changes(BankId::D1), d1 + 1) << "the same values again are no change";
  store.set_online(BankId::D1, true);
  EXPECT_EQ(store.changes(BankId::D1), d1 + 2);
  EXPECT_GT(store.changes(BankId::C), c) << "C's on-line bits";
  const auto c_before_error = store.changes(BankId::C);
  store.set_modbus_error(true);
  store.set_modbus_error(true);
  EXPECT_EQ(store.changes(BankId::C), c_before_error + 1);
  store.set_user_output(1, 5);
  EXPECT_EQ(store.changes(BankId::C), c_before_error + 2);
  store.write(BankId::W, 0, 1);
  EXPECT_GT(store.changes(BankId::W), 0u);
}

TEST(RegisterStore, ABankTheMappingReadsCountsForAAndB) {
  RegisterStore store(shapes_with({&chp(), &chp(), nullptr, nullptr}));
  Mapping mapping;
  mapping.analog[0] = SourceRef{BankId::D1, 1, std::nullopt, "D1+0x01"};
  store.set_mapping(mapping);
  const auto a = store.changes(BankId::A);
  const auto b = store.changes(BankId::B);
  const std::array<std::uint16_t, 1> value{1500};
  ASSERT_TRUE(store.store_telegram(BankId::D1, 1, value));
  EXPECT_EQ(store.changes(BankId::A), a + 1);
  EXPECT_EQ(store.changes(BankId::B), b + 1);
  ASSERT_TRUE(store.store_telegram(BankId::D2, 1, value));
  EXPECT_EQ(store.changes(BankId::A), a + 1) << "D2 feeds no mapping entry";
}

TEST(RegisterStore, TheChangeSignalComesOncePerArming) {
  RegisterStore store(shapes_with({&chp(), nullptr, nullptr, nullptr}));
  int signals = 0;
  store.set_change_signal([&] { ++signals; });
  const std::array<std::uint16_t, 1> one{1}, two{2}, three{3};
  store.store_telegram(BankId::D1, 0, one);
  EXPECT_EQ(signals, 0) << "not armed";
  store.arm_change_signal();
  store.store_telegram(BankId::D1, 0, two);
  store.store_telegram(BankId::D1, 0, three);
  EXPECT_EQ(signals, 1);
  store.arm_change_signal();
  store.store_telegram(BankId::D1, 0, three);
  EXPECT_EQ(signals, 1) << "no change, no signal";
  store.set_online(BankId::D1, true);
  EXPECT_EQ(signals, 2);
}

TEST(RegisterStore, TakeStateFromCarriesPublishedValuesAndSameTableDevices) {
  const DeviceTable* uvr = find_device_type("uvr");
  ASSERT_NE(uvr, nullptr);
  RegisterStore old(shapes_with({&chp(), &chp(), nullptr, nullptr}));
  old.write(BankId::W, 0, 42);
  old.write(BankId::W, 15, 4242);
  old.write(BankId::X, 0, 0x0101);
  old.set_user_output(5, 555);
  const std::vector<std::uint16_t> values = {853, 854};
  old.store_telegram(BankId::D1, 0x21, values);
  old.store_telegram(BankId::D2, 0x21, values);
  old.set_online(BankId::D1, true);
  old.set_online(BankId::D2, true);

  // D1 keeps its table, D2 changes type.
  RegisterStore fresh(shapes_with({&chp(), uvr, nullptr, nullptr}));
  std::vector<Change> changes;
  fresh.set_change_listener([&](BankId b, std::uint16_t o, std::uint16_t v) { changes.push_back({b, o, v}); });
  fresh.take_state_from(old);

  EXPECT_EQ(fresh.read(BankId::W, 0), 42);
  EXPECT_EQ(fresh.read(BankId::W, 15), 4242);
  EXPECT_EQ(fresh.read(BankId::W, 1), 0x7FFF);
  EXPECT_EQ(fresh.read(BankId::X, 0), 0x0101);
  EXPECT_EQ(fresh.read(BankId::C, 4), 555);
  fresh.set_online(BankId::D1, true);
  EXPECT_EQ(fresh.read(BankId::D1, 0x21), 853);
  EXPECT_EQ(fresh.read(BankId::D1, 0x22), 854);
  EXPECT_EQ(fresh.read(BankId::D1, 0x20), offline_value(chp().registers[0x20].kind));
  // The new D2 table is another device: nothing of the old values.
  EXPECT_EQ(fresh.filled_length(BankId::D2), uvr->length());
  fresh.set_online(BankId::D2, true);
  EXPECT_EQ(fresh.read(BankId::D2, 0x21), offline_value(uvr->registers[0x21].kind));
  EXPECT_EQ(fresh.read(BankId::D2, 0x22), offline_value(uvr->registers[0x22].kind));
  // The old store's listener is untouched, the fresh store's still works.
  fresh.write(BankId::W, 1, 7);
  ASSERT_FALSE(changes.empty());
  EXPECT_EQ(changes.back(), (Change{BankId::W, 1, 7}));
}

}  // namespace
}  // namespace unima::banks
