// banks::WritePath, the one way a value from outside gets into W, X or a write block's
// output: rights before anything, all or nothing, a write kept whole in the journal and
// the number the answer waits for, and nothing in the store or published (the store's
// change listener) before the journal holds it: a refused write changes nothing.

#include <gtest/gtest.h>

#include <array>
#include <deque>
#include <tuple>
#include <vector>

#include "banks/table_catalog.hpp"
#include "banks/write_path.hpp"
#include "tests/support/bank_layouts.hpp"

namespace unima::banks {
namespace {

using Status = modbus::WriteResult::Status;
using Value = std::tuple<BankId, std::uint16_t, std::uint16_t>;

Window write_block(std::uint16_t address, std::uint8_t output) {
  Window w;
  w.kind = Window::Kind::write_block;
  w.first = address;
  w.count = 1;
  w.output = output;
  w.name = "write block";
  return w;
}

// Numbers its writes from 1, as io::StateFile does, and holds them until the test says
// what the disk made of the oldest: durable (committed into `committer`) or refused.
struct Journal final : WriteJournal {
  std::uint64_t keep(std::span<const WrittenValue> write) override {
    writes.emplace_back();
    for (const auto& v : write) {
      kept.emplace_back(v.bank, v.offset, v.value);
      writes.back().emplace_back(v);
    }
    waiting.emplace_back(writes.size(), writes.back());
    return writes.size();
  }
  std::optional<std::uint16_t> pending(BankId bank, std::uint16_t offset) const override {
    for (auto write = waiting.rbegin(); write != waiting.rend(); ++write)
      for (auto v = write->second.rbegin(); v != write->second.rend(); ++v)
        if (v->bank == bank && v->offset == offset) return v->value;
    return std::nullopt;
  }
  /// The oldest waiting write is durable (true) or refused; returns its number.
  std::uint64_t settle(bool durable) {
    const auto [number, write] = waiting.front();
    waiting.pop_front();
    if (durable) committer->commit(write);
    return number;
  }
  void settle_all() {
    while (!waiting.empty()) settle(true);
  }
  WritePath* committer = nullptr;
  std::vector<Value> kept;                           // every value, in the order kept
  std::vector<std::vector<WrittenValue>> writes;     // by write
  std::deque<std::pair<std::uint64_t, std::vector<WrittenValue>>> waiting;
};

struct WritePathTest : ::testing::Test {
  WritePathTest() {
    store.set_change_listener([this](BankId b, std::uint16_t o, std::uint16_t v) { published.emplace_back(b, o, v); });
    journal.committer = &writes;
  }

  RegisterStore store{shapes_with({&chp(), nullptr, nullptr, nullptr})};
  RegisterSpace space{AddressMap({bank_window(BankId::A, 0x1000, 16), bank_window(BankId::C, 0x1020, 20),
                                  bank_window(BankId::D1, 0x1100, 64), bank_window(BankId::W, 0x3000, 16),
                                  bank_window(BankId::X, 0x3010, 1), write_block(0x4000, 3)}),
                      store, AccessRules{}};
  Journal journal;
  WritePath writes{space, &journal};
  std::vector<Value> published;
};

TEST_F(WritePathTest, AWriteIntoWIsKeptAsOneAndLandsAndIsPublishedOnlyOnceDurable) {
  const std::array<std::uint16_t, 2> values = {7, 8};
  const auto result = writes.write_registers(0x3002, values, nullptr);
  EXPECT_EQ(result.status, Status::written);
  EXPECT_EQ(result.kept_as, 1u);  // one write, its two values together: the answer waits for both
  ASSERT_EQ(journal.writes.size(), 1u);
  const std::vector<Value> expected = {{BankId::W, 2, 7}, {BankId::W, 3, 8}};
  EXPECT_EQ(journal.kept, expected);
  // Kept, not yet durable: nothing changed, nothing went to UnimaBUS.
  EXPECT_EQ(store.read(BankId::W, 2), 0x7FFF);
  EXPECT_FALSE(store.written(BankId::W, 2));
  EXPECT_TRUE(published.empty());
  journal.settle(true);
  EXPECT_EQ(store.read(BankId::W, 2), 7);
  EXPECT_EQ(store.read(BankId::W, 3), 8);
  EXPECT_EQ(published, expected);
}

TEST_F(WritePathTest, AWriteTheJournalRefusesChangesNothingAndPublishesNothing) {
  const std::array<std::uint16_t, 3> values = {7, 8, 9};
  EXPECT_EQ(writes.write_registers(0x3002, values, nullptr).status, Status::written);
  const std::array<std::uint16_t, 1> bits = {0x0001};
  EXPECT_EQ(writes.write_registers(0x3010, bits, nullptr).status, Status::written);
  journal.settle(false);
  journal.settle(false);
  for (std::uint16_t i = 0; i < 16; ++i) EXPECT_EQ(store.read(BankId::W, i), 0x7FFF) << i;
  EXPECT_EQ(store.read(BankId::X, 0), 0);
  EXPECT_TRUE(published.empty());
  // The next write, once durable, is taken as usual.
  const std::array<std::uint16_t, 1> value = {5};
  writes.write_registers(0x3002, value, nullptr);
  journal.settle(true);
  EXPECT_EQ(store.read(BankId::W, 2), 5);
  EXPECT_EQ(store.read(BankId::W, 3), 0x7FFF);
  EXPECT_EQ(published, (std::vector<Value>{{BankId::W, 2, 5}}));
}

TEST_F(WritePathTest, WritesThatWaitTogetherLandInTheOrderTheyWereKept) {
  const std::array<std::uint16_t, 1> first = {1}, second = {2};
  writes.write_registers(0x3005, first, nullptr);
  writes.write_registers(0x3005, second, nullptr);
  EXPECT_EQ(store.read(BankId::W, 5), 0x7FFF);  // neither is durable yet
  journal.settle_all();
  EXPECT_EQ(store.read(BankId::W, 5), 2);
  EXPECT_EQ(published, (std::vector<Value>{{BankId::W, 5, 1}, {BankId::W, 5, 2}}));
}

TEST_F(WritePathTest, AWriteAcrossWIntoXTakesBoth) {
  const std::array<std::uint16_t, 2> across = {0x1111, 0x0003};
  EXPECT_EQ(writes.write_registers(0x300F, across, nullptr).status, Status::written);
  journal.settle_all();
  EXPECT_EQ(store.read(BankId::W, 15), 0x1111);
  EXPECT_EQ(store.read(BankId::X, 0), 0x0003);
  const std::vector<Value> expected = {{BankId::W, 15, 0x1111}, {BankId::X, 0, 0x0003}};
  EXPECT_EQ(journal.kept, expected);
}

TEST_F(WritePathTest, AWriteBlockKeepsItsUserOutputAtItsOffsetInC) {
  const std::array<std::uint16_t, 1> value = {555};
  EXPECT_EQ(writes.write_registers(0x4000, value, nullptr).status, Status::written);
  journal.settle_all();
  EXPECT_EQ(store.read(BankId::C, c_bank::user_analog_outputs + 2), 555);
  const std::vector<Value> expected = {{BankId::C, c_bank::user_analog_outputs + 2, 555}};
  EXPECT_EQ(journal.kept, expected);
}

TEST_F(WritePathTest, AReadOnlyRegisterRefusesAndNothingIsWrittenKeptOrPublished) {
  store.set_online(BankId::D1, true);
  const std::array<std::uint16_t, 1> value = {1234};
  for (const std::uint16_t address : {0x1100, 0x1121, 0x1020, 0x1000})  // D1, D1, C, A
    EXPECT_EQ(writes.write_registers(address, value, nullptr).status, Status::not_writable) << address;
  EXPECT_EQ(store.read(BankId::C, 0), 0x7FFF);
  EXPECT_TRUE(journal.kept.empty());
  EXPECT_TRUE(published.empty());
}

TEST_F(WritePathTest, ARangePartlyOutsideTheWritableRegistersWritesNothing) {
  const std::array<std::uint16_t, 3> three = {1, 2, 3};
  EXPECT_EQ(writes.write_registers(0x300F, three, nullptr).status, Status::not_writable);  // W+15, X, then a gap
  const std::array<std::uint16_t, 2> two = {1, 2};
  EXPECT_EQ(writes.write_registers(0x2FFF, two, nullptr).status, Status::not_writable);  // a gap, then W+0
  EXPECT_EQ(writes.write_registers(0xFFFF, two, nullptr).status, Status::not_writable);  // past the top
  EXPECT_EQ(writes.write_registers(0x3000, std::span<const std::uint16_t>(), nullptr).status, Status::not_writable);
  for (std::uint16_t i = 0; i < 16; ++i) EXPECT_EQ(store.read(BankId::W, i), 0x7FFF) << i;
  EXPECT_EQ(store.read(BankId::X, 0), 0);
  EXPECT_TRUE(journal.kept.empty());
}

TEST_F(WritePathTest, RightsComeFirstAndRefuseEvenWhereThereIsNoRegister) {
  auto rights = modbus::WriteRights::nothing();
  rights.allow(0x3000, 0x3001);
  const std::array<std::uint16_t, 2> two = {1, 2};
  EXPECT_EQ(writes.write_registers(0x3001, two, &rights).status, Status::not_allowed);  // W+2 is not the role's
  EXPECT_EQ(writes.write_registers(0x1100, two, &rights).status, Status::not_allowed);  // says nothing of the map
  const auto nothing = modbus::WriteRights::nothing();
  EXPECT_EQ(writes.write_bit(0x3010, 0, true, &nothing).status, Status::not_allowed);
  EXPECT_TRUE(journal.kept.empty());
  EXPECT_EQ(writes.write_registers(0x3000, two, &rights).status, Status::written);
  journal.settle_all();
  EXPECT_EQ(store.read(BankId::W, 1), 2);
}

TEST_F(WritePathTest, ABitOfXIsSetAndClearedLeavingTheOthers) {
  const std::array<std::uint16_t, 1> bits = {0x0005};
  writes.write_registers(0x3010, bits, nullptr);
  journal.settle_all();
  EXPECT_EQ(writes.write_bit(0x3010, 3, true, nullptr).status, Status::written);
  journal.settle_all();
  EXPECT_EQ(store.read(BankId::X, 0), 0x000D);
  const auto result = writes.write_bit(0x3010, 0, false, nullptr);
  journal.settle_all();
  EXPECT_EQ(store.read(BankId::X, 0), 0x000C);
  EXPECT_EQ(result.kept_as, 3u);
  EXPECT_EQ(journal.kept.back(), Value(BankId::X, 0, 0x000C));
}

// Two MQTT bit commands in one turn: the second builds on the first, which is not in the
// store yet, so neither bit is lost.
TEST_F(WritePathTest, ABitBuildsOnTheLatestPendingWriteNotOnTheStore) {
  const std::array<std::uint16_t, 1> bits = {0x0005};
  writes.write_registers(0x3010, bits, nullptr);
  writes.write_bit(0x3010, 3, true, nullptr);
  writes.write_bit(0x3010, 0, false, nullptr);
  EXPECT_EQ(store.read(BankId::X, 0), 0);  // none durable yet
  EXPECT_EQ(journal.kept.back(), Value(BankId::X, 0, 0x000C));
  journal.settle_all();
  EXPECT_EQ(store.read(BankId::X, 0), 0x000C);
  // Once nothing is pending, the store is what a bit builds on again.
  writes.write_bit(0x3010, 1, true, nullptr);
  EXPECT_EQ(journal.kept.back(), Value(BankId::X, 0, 0x000E));
}

TEST_F(WritePathTest, ABitBuildsOnTheStoreAgainOnceThePendingWriteIsRefused) {
  const std::array<std::uint16_t, 1> bits = {0x0005};
  writes.write_registers(0x3010, bits, nullptr);
  journal.settle_all();
  writes.write_bit(0x3010, 3, true, nullptr);  // 0x000D, refused
  journal.settle(false);
  writes.write_bit(0x3010, 1, true, nullptr);
  EXPECT_EQ(journal.kept.back(), Value(BankId::X, 0, 0x0007));
}

TEST_F(WritePathTest, ABitOfAWriteOnlyXIsStillReadModifyWrite) {
  RegisterSpace strict(space.map(), store, AccessRules{false});
  WritePath strict_writes(strict, &journal);
  journal.committer = &strict_writes;
  const std::array<std::uint16_t, 1> bits = {0x0100};
  strict_writes.write_registers(0x3010, bits, nullptr);
  journal.settle_all();
  strict_writes.write_bit(0x3010, 1, true, nullptr);
  journal.settle_all();
  EXPECT_EQ(store.read(BankId::X, 0), 0x0102);
}

TEST_F(WritePathTest, WithoutAJournalNothingIsKeptAndTheAnswerNeedNotWait) {
  WritePath unkept(space, nullptr);
  const std::array<std::uint16_t, 1> value = {9};
  const auto result = unkept.write_registers(0x3000, value, nullptr);
  EXPECT_EQ(result.status, Status::written);
  EXPECT_EQ(result.kept_as, 0u);
  EXPECT_EQ(store.read(BankId::W, 0), 9);
  EXPECT_EQ(published, (std::vector<Value>{{BankId::W, 0, 9}}));
}

}  // namespace
}  // namespace unima::banks
