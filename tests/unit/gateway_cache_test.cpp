// The gateway's read cache (SPEC §14): an equal read within the window gets the answer
// again, a write empties its unit's answers, exceptions are never kept, and the number of
// answers kept is bounded; driven by simulated time.

#include <gtest/gtest.h>

#include "master/gateway_cache.hpp"

namespace unima::master {
namespace {

using namespace std::chrono_literals;
using Bytes = GatewayCache::Bytes;
using TimePoint = GatewayCache::TimePoint;

const TimePoint t0 = TimePoint{} + 1000s;
const Bytes read_d0{0x03, 0x00, 0x00, 0x00, 0x01};
const Bytes d0_is_42{0x03, 0x02, 0x00, 0x2A};

Bytes read_register(std::uint16_t address) {
  return {0x03, static_cast<std::uint8_t>(address >> 8), static_cast<std::uint8_t>(address & 0xFF), 0x00, 0x01};
}

TEST(GatewayCache, AnEqualReadWithinTheWindowGetsTheSameAnswer) {
  GatewayCache cache(500ms);
  EXPECT_FALSE(cache.answer(5, read_d0, t0));
  cache.answered(5, read_d0, d0_is_42, t0);
  EXPECT_EQ(cache.answer(5, read_d0, t0 + 499ms), d0_is_42);
  EXPECT_FALSE(cache.answer(5, read_d0, t0 + 500ms)) << "the window is over";
  EXPECT_EQ(cache.size(), 0u) << "an answer past its window is forgotten";
}

TEST(GatewayCache, OnlyTheSameUnitAndTheSamePduBytesAreEqual) {
  GatewayCache cache(1s);
  cache.answered(5, read_d0, d0_is_42, t0);
  EXPECT_FALSE(cache.answer(6, read_d0, t0));
  EXPECT_FALSE(cache.answer(5, Bytes{0x03, 0x00, 0x00, 0x00, 0x02}, t0));
  EXPECT_FALSE(cache.answer(5, Bytes{0x04, 0x00, 0x00, 0x00, 0x01}, t0));
  EXPECT_TRUE(cache.answer(5, read_d0, t0));
}

TEST(GatewayCache, FunctionsOneToFourAreReadsEveryOtherIsNot) {
  for (const std::uint8_t function : {1, 2, 3, 4}) EXPECT_TRUE(GatewayCache::is_read(Bytes{function, 0, 0, 0, 1}));
  for (const std::uint8_t function : {0, 5, 6, 7, 8, 15, 16, 17, 22, 23, 43, 0x83})
    EXPECT_FALSE(GatewayCache::is_read(Bytes{function, 0, 0, 0, 1})) << int(function);
  EXPECT_FALSE(GatewayCache::is_read(Bytes{}));
}

// Function 23 reads too, but it writes first: its answer is never kept.
TEST(GatewayCache, AWriteIsNeverKeptNorAnswered) {
  GatewayCache cache(1s);
  const Bytes write_d0{0x06, 0x00, 0x00, 0x00, 0x2A};
  cache.answered(5, write_d0, write_d0, t0);
  const Bytes read_write{0x17, 0x00, 0x00, 0x00, 0x01, 0x00, 0x01, 0x00, 0x01, 0x02, 0x00, 0x07};
  cache.answered(5, read_write, Bytes{0x17, 0x02, 0x00, 0x07}, t0);
  EXPECT_EQ(cache.size(), 0u);
  EXPECT_FALSE(cache.answer(5, write_d0, t0));
}

TEST(GatewayCache, AnExceptionIsNotKept) {
  GatewayCache cache(1s);
  cache.answered(5, read_d0, Bytes{0x83, 0x02}, t0);
  EXPECT_FALSE(cache.answer(5, read_d0, t0));
  cache.answered(5, read_d0, Bytes{}, t0);  // nothing came
  EXPECT_EQ(cache.size(), 0u);
}

TEST(GatewayCache, AWriteEmptiesItsUnitsAnswersOnly) {
  GatewayCache cache(1s);
  cache.answered(5, read_d0, d0_is_42, t0);
  cache.answered(5, read_register(7), d0_is_42, t0);
  cache.answered(6, read_d0, d0_is_42, t0);
  cache.written(5);
  EXPECT_FALSE(cache.answer(5, read_d0, t0));
  EXPECT_FALSE(cache.answer(5, read_register(7), t0));
  EXPECT_EQ(cache.size(5), 0u);
  EXPECT_EQ(cache.answer(6, read_d0, t0), d0_is_42);
}

TEST(GatewayCache, ANewerAnswerReplacesTheOlderAndItsWindowStartsAgain) {
  GatewayCache cache(1s);
  cache.answered(5, read_d0, d0_is_42, t0);
  const Bytes d0_is_43{0x03, 0x02, 0x00, 0x2B};
  cache.answered(5, read_d0, d0_is_43, t0 + 800ms);
  EXPECT_EQ(cache.size(), 1u);
  EXPECT_EQ(cache.answer(5, read_d0, t0 + 1500ms), d0_is_43);
}

TEST(GatewayCache, OffItKeepsNothing) {
  GatewayCache cache(0ms);
  cache.answered(5, read_d0, d0_is_42, t0);
  EXPECT_EQ(cache.size(), 0u);
  EXPECT_FALSE(cache.answer(5, read_d0, t0));
}

// A client scanning addresses: the unit keeps its newest `per_unit` answers.
TEST(GatewayCache, AUnitKeepsItsNewestAnswersUpToItsBound) {
  GatewayCache cache(1h, 4, 100);
  for (std::uint16_t a = 0; a < 1000; ++a) cache.answered(5, read_register(a), d0_is_42, t0 + a * 1ms);
  EXPECT_EQ(cache.size(5), 4u);
  EXPECT_EQ(cache.size(), 4u);
  EXPECT_FALSE(cache.answer(5, read_register(995), t0 + 1s));
  for (std::uint16_t a = 996; a < 1000; ++a) EXPECT_TRUE(cache.answer(5, read_register(a), t0 + 1s)) << a;
}

// Many units: all of them together keep the newest `total` answers.
TEST(GatewayCache, AllUnitsTogetherKeepTheNewestAnswersUpToTheTotal) {
  GatewayCache cache(1h, 4, 10);
  for (std::uint8_t unit = 1; unit <= 100; ++unit)
    for (std::uint16_t a = 0; a < 3; ++a) cache.answered(unit, read_register(a), d0_is_42, t0 + unit * 10ms + a * 1ms);
  EXPECT_EQ(cache.size(), 10u);
  EXPECT_FALSE(cache.answer(96, read_register(2), t0 + 2s));
  EXPECT_FALSE(cache.answer(97, read_register(1), t0 + 2s));
  EXPECT_TRUE(cache.answer(97, read_register(2), t0 + 2s));
  EXPECT_TRUE(cache.answer(100, read_register(2), t0 + 2s));
  EXPECT_EQ(cache.size(100), 3u);
  EXPECT_EQ(cache.size(96), 0u);
}

TEST(GatewayCache, TheDefaultBoundsAreSixtyFourPerUnitAndOneThousandTwentyFourInAll) {
  GatewayCache cache(1h);
  for (std::uint8_t unit = 1; unit <= 20; ++unit)
    for (std::uint16_t a = 0; a < 100; ++a) cache.answered(unit, read_register(a), d0_is_42, t0);
  EXPECT_EQ(cache.size(20), 64u);
  EXPECT_EQ(cache.size(), 1024u);
}

}  // namespace
}  // namespace unima::master
