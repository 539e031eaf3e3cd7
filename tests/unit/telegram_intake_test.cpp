// unimabus::TelegramIntake, a telegram's owner: routed into its bank, recorded, counted,
// its device on-line in the store until it falls silent, and all of it across a reload.

#include <gtest/gtest.h>

#include <chrono>
#include <vector>

#include "banks/table_catalog.hpp"
#include "unimabus/telegram_intake.hpp"

namespace unima::unimabus {
namespace {

using banks::BankId;
using namespace std::chrono_literals;
using Change = TelegramIntake::PresenceChange;

const TelegramIntake::Clock::time_point t0{};
constexpr std::uint8_t bridge_address = 1;

banks::BankShapes shapes(const char* d1, const char* d2) {
  return banks::standard_shapes({banks::find_device_type(d1), banks::find_device_type(d2), nullptr, nullptr},
                                banks::io_module_table(), banks::bridge_internal_table());
}

struct Recorded final : TelegramRecording {
  void record(const Telegram& telegram, std::chrono::steady_clock::time_point now) override {
    telegrams.push_back(telegram);
    times.push_back(now);
  }
  std::vector<Telegram> telegrams;
  std::vector<std::chrono::steady_clock::time_point> times;
};

struct Plant {
  Plant(const char* d1, const char* d2, std::chrono::seconds offline_after)
      : store(shapes(d1, d2)),
        intake(standard_routes(bridge_address, store, {{BankId::D1, 5}, {BankId::D2, 6}}), store, offline_after) {}
  banks::RegisterStore store;
  TelegramIntake intake;
};

TEST(TelegramIntake, ATelegramIsStoredCountedAndBringsItsDeviceOnLineOnce) {
  Plant plant("unigen-chp", "unigen-chp", 5s);
  auto taken = plant.intake.take(Telegram{5, 0, 1, {853}}, t0);
  EXPECT_TRUE(taken.error.empty());
  EXPECT_EQ(taken.changes, (std::vector<Change>{{BankId::D1, true}}));
  EXPECT_TRUE(plant.store.online(BankId::D1));
  EXPECT_EQ(plant.store.read(BankId::D1, 1), 853);
  EXPECT_EQ(plant.store.online_bits() & 0x1, 0x1);
  taken = plant.intake.take(Telegram{5, 0, 1, {854}}, t0 + 1s);
  EXPECT_TRUE(taken.changes.empty());  // already on-line
  EXPECT_EQ(plant.intake.counts().taken[banks::index_of(BankId::D1)], 2u);
  EXPECT_EQ(plant.intake.last_telegram(), t0 + 1s);
  EXPECT_EQ(plant.intake.next_expiry(), t0 + 6s);
}

TEST(TelegramIntake, AnotherDevicesTelegramIsIgnoredAndOnePastTheEndRefused) {
  Plant plant("unigen-chp", "unigen-chp", 5s);
  EXPECT_TRUE(plant.intake.take(Telegram{9, 0, 0, {1}}, t0).error.empty());
  const auto refused = plant.intake.take(Telegram{5, 0, 63, {1, 2}}, t0);
  EXPECT_NE(refused.error.find("past the end of bank D1"), std::string::npos) << refused.error;
  EXPECT_TRUE(refused.changes.empty());
  EXPECT_FALSE(plant.store.online(BankId::D1));  // a refused telegram is not a sign of life
  EXPECT_EQ(plant.intake.counts().ignored, 1u);
  EXPECT_EQ(plant.intake.counts().refused, 1u);
  EXPECT_EQ(plant.intake.counts().taken[banks::index_of(BankId::D1)], 0u);
  EXPECT_EQ(plant.intake.counts().received, 2u);  // the UnimaBUS LED blinks for both (SPEC §8)
}

TEST(TelegramIntake, EveryTelegramIsRecordedTakenOrNot) {
  Plant plant("unigen-chp", "unigen-chp", 5s);
  Recorded recorded;
  plant.intake.set_recording(&recorded);
  plant.intake.take(Telegram{5, 0, 1, {853}}, t0);
  plant.intake.take(Telegram{9, 0, 0, {1}}, t0 + 1s);  // another device's
  ASSERT_EQ(recorded.telegrams.size(), 2u);
  EXPECT_EQ(recorded.telegrams[1].address, 9);
  EXPECT_EQ(recorded.times[1], t0 + 1s);
}

TEST(TelegramIntake, ASilentDeviceGoesOffLineInTheStore) {
  Plant plant("unigen-chp", "unigen-chp", 5s);
  plant.intake.take(Telegram{5, 0, 1, {853}}, t0);
  plant.intake.take(Telegram{6, 0, 1, {900}}, t0 + 2s);
  EXPECT_TRUE(plant.intake.expire(t0 + 4s).empty());
  EXPECT_EQ(plant.intake.expire(t0 + 5s), (std::vector<Change>{{BankId::D1, false}}));
  EXPECT_FALSE(plant.store.online(BankId::D1));
  EXPECT_EQ(plant.store.read(BankId::D1, 1), 0x7FFF);  // SPEC §1: off-line reads "not measured"
  EXPECT_TRUE(plant.store.online(BankId::D2));
  EXPECT_EQ(plant.intake.next_expiry(), t0 + 7s);
}

// A reload keeps a device on-line only when it was on-line and the new config kept its
// values (same table); the counts go on.
TEST(TelegramIntake, AReloadKeepsOnLineOnlyTheDevicesWhoseValuesItKept) {
  Plant old("unigen-chp", "unigen-chp", 5s);
  old.intake.take(Telegram{5, 0, 1, {853}}, t0);
  old.intake.take(Telegram{6, 0, 1, {900}}, t0);
  Plant fresh("unigen-chp", "uis", 10s);  // D2 changes its table
  fresh.store.take_state_from(old.store);
  const auto changes = fresh.intake.take_over(old.intake, t0 + 3s);
  EXPECT_EQ(changes, (std::vector<Change>{{BankId::D2, false}}));
  EXPECT_TRUE(fresh.store.online(BankId::D1));
  EXPECT_EQ(fresh.store.read(BankId::D1, 1), 853);
  EXPECT_FALSE(fresh.store.online(BankId::D2));
  EXPECT_FALSE(fresh.store.online(BankId::D3));  // never heard
  EXPECT_EQ(fresh.intake.next_expiry(), t0 + 13s);  // heard at the reload, under the new limit
  EXPECT_EQ(fresh.intake.counts().taken[banks::index_of(BankId::D2)], 1u);
  EXPECT_EQ(fresh.intake.last_telegram(), t0);
}

}  // namespace
}  // namespace unima::unimabus
