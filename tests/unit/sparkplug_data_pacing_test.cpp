// sparkplug/data_pacing: a change after a quiet while is looked at at once, changes close
// together wait for one look, never two looks within the interval.
#include "sparkplug/data_pacing.hpp"

#include <gtest/gtest.h>

namespace {

using unima::sparkplug::DataPacing;
using namespace std::chrono_literals;

const DataPacing::Clock::time_point t0{std::chrono::seconds(1000)};

TEST(SparkplugDataPacing, TheFirstChangeIsLookedAtAtOnce) {
  DataPacing pacing;
  EXPECT_EQ(pacing.changed(t0), t0);
}

TEST(SparkplugDataPacing, ChangesBeforeTheLookJoinIt) {
  DataPacing pacing;
  ASSERT_EQ(pacing.changed(t0), t0);
  EXPECT_EQ(pacing.changed(t0), std::nullopt);
  EXPECT_EQ(pacing.changed(t0 + 1ms), std::nullopt);
}

TEST(SparkplugDataPacing, AChangeSoonAfterALookWaitsForTheInterval) {
  DataPacing pacing;
  pacing.changed(t0);
  pacing.looked(t0);
  EXPECT_EQ(pacing.changed(t0 + 3ms), t0 + DataPacing::interval);
  EXPECT_EQ(pacing.changed(t0 + 4ms), std::nullopt);  // the same look takes it
  pacing.looked(t0 + DataPacing::interval);
  EXPECT_EQ(pacing.changed(t0 + DataPacing::interval + 1ms), t0 + 2 * DataPacing::interval);
}

TEST(SparkplugDataPacing, AChangeAfterAQuietIntervalGoesAtOnce) {
  DataPacing pacing;
  pacing.looked(t0);
  EXPECT_EQ(pacing.changed(t0 + DataPacing::interval), t0 + DataPacing::interval);
  pacing.looked(t0 + DataPacing::interval);
  EXPECT_EQ(pacing.changed(t0 + 5s), t0 + 5s);
}

// 1,000 changes a second for a second, each looked at when due: about 1000 ms ÷ interval
// looks, none closer than the interval, and no change waits longer than the interval.
TEST(SparkplugDataPacing, AThousandChangesASecondMakeOneLookPerInterval) {
  DataPacing pacing;
  bool due = false;
  auto due_at = t0;
  auto last_look = t0 - std::chrono::hours(1);
  auto oldest_waiting = t0;
  bool waiting = false;
  int looks = 0;
  const auto look_if_due = [&](DataPacing::Clock::time_point now) {
    if (!due || due_at > now) return;
    pacing.looked(now);
    EXPECT_GE(now - last_look, DataPacing::interval);
    EXPECT_LE(now - oldest_waiting, DataPacing::interval);
    last_look = now;
    due = false;
    waiting = false;
    ++looks;
  };
  for (int ms = 0; ms < 1000; ++ms) {
    const auto now = t0 + std::chrono::milliseconds(ms);
    look_if_due(now);
    if (!waiting) {
      oldest_waiting = now;
      waiting = true;
    }
    if (const auto at = pacing.changed(now)) {
      due = true;
      due_at = *at;
    }
    look_if_due(now);  // at once: the loop's next turn
  }
  EXPECT_GE(looks, 95);
  EXPECT_LE(looks, 101);
}

TEST(SparkplugDataPacing, ALookThatCouldNotPublishIsTriedAgainAfterTheInterval) {
  DataPacing pacing;
  ASSERT_EQ(pacing.changed(t0), t0);
  EXPECT_EQ(pacing.retry(t0), t0 + DataPacing::interval);
  EXPECT_EQ(pacing.changed(t0 + 1ms), std::nullopt);  // the retry takes it
}

}  // namespace
