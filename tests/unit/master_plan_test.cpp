// The master's plan (seed 004 §7.2): consecutive poll blocks of one device share a request
// at the shortest period; gaps, limits, splitting after exception 02, and the bus load.

#include <gtest/gtest.h>

#include <set>

#include "master/master_codec.hpp"
#include "master/master_plan.hpp"

namespace unima::master {
namespace {

using namespace std::chrono_literals;

MasterBlock poll(std::uint8_t device, std::uint16_t reg, std::chrono::milliseconds period, std::uint16_t count = 1,
                 std::uint8_t fn = 4) {
  MasterBlock b;
  b.device = device;
  b.function = fn;
  b.reg = reg;
  b.count = count;
  b.period = period;
  return b;
}

MasterBlock send(std::uint8_t device, std::uint16_t reg, std::chrono::milliseconds period) {
  MasterBlock b = poll(device, reg, period, 1, 6);
  b.kind = MasterBlock::Kind::send;
  return b;
}

TEST(MasterPlan, ConsecutiveReadsShareOneRequestAtTheShortestPeriod) {
  const std::vector<MasterBlock> blocks{poll(1, 0x0201, 2s), poll(1, 0x0200, 1s), poll(1, 0x0202, 5s)};
  const auto plan = plan_requests(blocks, {});
  ASSERT_EQ(plan.size(), 1u);
  EXPECT_EQ(plan[0].first, 0x0200);
  EXPECT_EQ(plan[0].count, 3);
  EXPECT_EQ(plan[0].period, 1s);
  EXPECT_EQ(plan[0].blocks, (std::vector<std::size_t>{1, 0, 2}));
  EXPECT_FALSE(plan[0].spans_gap);
}

TEST(MasterPlan, DevicesFunctionsAndGapsKeepRequestsApart) {
  const std::vector<MasterBlock> blocks{poll(1, 10, 1s), poll(2, 11, 1s), poll(1, 11, 1s, 1, 3), poll(1, 13, 1s)};
  const auto plan = plan_requests(blocks, {});
  ASSERT_EQ(plan.size(), 4u);
  EXPECT_EQ(plan[0].device, 1);
  EXPECT_EQ(plan[0].first, 10);
  EXPECT_EQ(plan[1].function, 3);
  EXPECT_EQ(plan[2].first, 13);
  EXPECT_EQ(plan[3].device, 2);
}

TEST(MasterPlan, OverlappingAndTwoRegisterBlocksMerge) {
  // POS_ACT_INT (1020, dint), VEL_ACT_INT (1024, dint) with merge_gap 2: 1020..1025.
  const std::vector<MasterBlock> blocks{poll(1, 1020, 200ms, 2, 3), poll(1, 1024, 500ms, 2, 3), poll(1, 1021, 1s, 1, 3)};
  PlanOptions options;
  options.merge_gap = 2;
  const auto plan = plan_requests(blocks, options);
  ASSERT_EQ(plan.size(), 1u);
  EXPECT_EQ(plan[0].first, 1020);
  EXPECT_EQ(plan[0].count, 6);
  EXPECT_TRUE(plan[0].spans_gap);
  EXPECT_EQ(plan[0].period, 200ms);
  options.merge_gap = 1;
  EXPECT_EQ(plan_requests(blocks, options).size(), 2u);
}

TEST(MasterPlan, RequestsStayWithinTheFunctionsMaximum) {
  std::vector<MasterBlock> blocks;
  for (std::uint16_t r = 0; r < 130; ++r) blocks.push_back(poll(1, r, 1s, 1, 3));
  const auto plan = plan_requests(blocks, {});
  ASSERT_EQ(plan.size(), 2u);
  EXPECT_EQ(plan[0].count, 125);
  EXPECT_EQ(plan[1].first, 125);
  EXPECT_EQ(plan[1].count, 5);
  PlanOptions small;
  small.max_read_registers = 10;
  EXPECT_EQ(plan_requests(blocks, small).size(), 13u);
}

TEST(MasterPlan, BitsMergeLikeRegisters) {
  std::vector<MasterBlock> blocks;
  for (std::uint16_t n = 0; n < 8; ++n) blocks.push_back(poll(1, 5000 + n, 100ms, 1, 2));
  const auto plan = plan_requests(blocks, {});
  ASSERT_EQ(plan.size(), 1u);
  EXPECT_EQ(plan[0].first, 5000);
  EXPECT_EQ(plan[0].count, 8);  // the seed's frame for IN1: 01 02 13 88 00 08
}

TEST(MasterPlan, SendsAreOneRequestEachAfterTheReadsOfTheirDevice) {
  const std::vector<MasterBlock> blocks{send(1, 0x0201, 2s), poll(1, 0x0200, 1s), send(1, 0x0202, 1s)};
  const auto plan = plan_requests(blocks, {});
  ASSERT_EQ(plan.size(), 3u);
  EXPECT_TRUE(plan[0].is_read());
  EXPECT_EQ(plan[1].first, 0x0201);
  EXPECT_EQ(plan[1].period, 2s);
  EXPECT_FALSE(plan[1].is_read());
  EXPECT_EQ(plan[2].first, 0x0202);
}

TEST(MasterPlan, SplitAfterIllegalDataAddress) {
  // STATUS (1002) and POS_ACT_INT (1020) merged over the gap 1003..1019.
  const std::vector<MasterBlock> blocks{poll(1, 1002, 1s, 1, 3), poll(1, 1003, 2s, 1, 3), poll(1, 1020, 500ms, 2, 3)};
  PlanOptions options;
  options.merge_gap = 20;
  const auto plan = plan_requests(blocks, options);
  ASSERT_EQ(plan.size(), 1u);
  ASSERT_TRUE(plan[0].spans_gap);
  const auto parts = split_request(plan[0], blocks);
  ASSERT_EQ(parts.size(), 2u);
  EXPECT_EQ(parts[0].first, 1002);
  EXPECT_EQ(parts[0].count, 2);
  EXPECT_EQ(parts[0].period, 1s);
  EXPECT_EQ(parts[1].first, 1020);
  EXPECT_EQ(parts[1].period, 500ms);
  // A gap-free merge splits into its blocks; a single block cannot split.
  const auto singles = split_request(parts[0], blocks);
  ASSERT_EQ(singles.size(), 2u);
  EXPECT_EQ(singles[1].first, 1003);
  EXPECT_EQ(singles[1].period, 2s);
  EXPECT_TRUE(split_request(singles[0], blocks).empty());
}

// When the split applies: exception 02 to a merged read, nothing else.
TEST(MasterPlan, SplitAfterOnlyForExceptionTwoToAMergedRead) {
  const std::vector<MasterBlock> blocks{poll(1, 1002, 1s, 1, 3), poll(1, 1020, 500ms, 2, 3)};
  PlanOptions options;
  options.merge_gap = 20;
  const auto merged = plan_requests(blocks, options).at(0);
  MasterResponse exception_02;
  exception_02.status = ResponseStatus::exception;
  exception_02.exception = modbus::ExceptionCode::illegal_data_address;
  EXPECT_EQ(split_after(merged, exception_02, blocks).size(), 2u);
  auto exception_03 = exception_02;
  exception_03.exception = modbus::ExceptionCode::illegal_data_value;
  EXPECT_TRUE(split_after(merged, exception_03, blocks).empty());
  MasterResponse timeout;
  timeout.status = ResponseStatus::timeout;
  EXPECT_TRUE(split_after(merged, timeout, blocks).empty());
  const auto single = split_request(merged, blocks).at(0);
  EXPECT_TRUE(split_after(single, exception_02, blocks).empty());  // the address is wrong, not the merge
}

TEST(MasterPlan, BusLoad) {
  // The line's times come from modbus::rtu_timing, pinned in rtu_framer_test.cpp.
  const auto line = modbus::rtu_timing(9600, false, 1);
  // Stepper §6 (1): 8 + 9 bytes each second at 9600 8N1, plus two t3.5.
  PlannedRequest r;
  r.function = 3;
  r.count = 2;
  r.period = 1s;
  EXPECT_EQ(rtu_request_size(r), 8u);
  EXPECT_EQ(rtu_response_size(r), 9u);
  const std::vector<PlannedRequest> plan{r};
  const auto load = estimate_load(plan, line);
  EXPECT_DOUBLE_EQ(load.requests_per_second, 1.0);
  EXPECT_NEAR(load.busy_fraction, (17 * 10.0 / 9600 + 2 * 0.003646), 1e-6);
  PlannedRequest write = r;
  write.function = 16;
  write.count = 2;
  EXPECT_EQ(rtu_request_size(write), 13u);  // seed 002 §6 (4)
  EXPECT_EQ(rtu_response_size(write), 8u);
  EXPECT_DOUBLE_EQ(device_request_rate(plan, 1), 1.0);
  EXPECT_DOUBLE_EQ(device_request_rate(plan, 2), 0.0);
}

}  // namespace
}  // namespace unima::master

namespace unima::master {
namespace {

using namespace std::chrono_literals;

PlannedRequest periodic(std::uint8_t device, std::chrono::milliseconds period) {
  PlannedRequest r;
  r.device = device;
  r.period = period;
  return r;
}

// The distance between two requests' occurrences, at their closest, in µs (chrono's count:
// 64 bits also where `long` has 32, as on armhf).
std::chrono::microseconds::rep closest(const PlannedRequest& a, const PlannedRequest& b) {
  using Micros = std::chrono::microseconds::rep;
  const Micros pa = std::chrono::duration_cast<std::chrono::microseconds>(a.period).count();
  const Micros pb = std::chrono::duration_cast<std::chrono::microseconds>(b.period).count();
  Micros best = pa * pb;
  for (Micros ta = a.phase.count(); ta < 10'000'000; ta += pa)
    for (Micros tb = b.phase.count(); tb < 10'000'000; tb += pb) best = std::min(best, std::abs(ta - tb));
  return best;
}

TEST(MasterPhases, RequestsThatWouldComeDueTogetherAreSpreadApart) {
  std::vector<PlannedRequest> plan{periodic(1, 100ms), periodic(1, 200ms), periodic(2, 250ms), periodic(3, 1000ms),
                                   periodic(3, 500ms)};
  const std::vector<std::chrono::microseconds> slots(plan.size(), 6000us);
  assign_phases(plan, slots, {{3, 35000us}});
  EXPECT_EQ(plan[0].phase, 0us);  // the shortest period goes first, at once
  for (std::size_t i = 0; i < plan.size(); ++i)
    for (std::size_t j = i + 1; j < plan.size(); ++j) {
      const std::chrono::microseconds::rep need = plan[i].device == 3 && plan[j].device == 3 ? 35000 : 6000;
      EXPECT_GE(closest(plan[i], plan[j]), need) << i << " and " << j;
    }
}

TEST(MasterPhases, PeriodsLongerThan35MinutesAreSpreadAsWell) {
  // 40 min is 2.4e9 µs, past a 32-bit long (armhf): counted so, the period went negative,
  // no offset was tried and both requests came due at once.
  std::vector<PlannedRequest> plan{periodic(1, 40min), periodic(1, 40min)};
  const std::vector<std::chrono::microseconds> slots(plan.size(), 5000us);
  assign_phases(plan, slots, {});
  EXPECT_EQ(plan[0].phase, 0us);
  EXPECT_GE(plan[1].phase, 5000us);
  EXPECT_LT(plan[1].phase, 2s);
}

TEST(MasterPhases, AnOverfullPlanStillGetsTheBestSpreadItCan) {
  // Ten 20 ms requests of 5 ms each cannot all keep 5 ms apart in 20 ms: the phases still
  // spread them as evenly as the search allows.
  std::vector<PlannedRequest> plan(10, periodic(1, 20ms));
  const std::vector<std::chrono::microseconds> slots(plan.size(), 5000us);
  assign_phases(plan, slots, {});
  std::set<std::chrono::microseconds::rep> phases;
  for (const auto& r : plan) phases.insert(r.phase.count());
  EXPECT_GE(phases.size(), 4u);
  for (const auto& r : plan) EXPECT_LT(r.phase, 20ms);
}

TEST(MasterPhases, TransactionEstimate) {
  PlannedRequest r;
  r.function = 3;
  r.count = 2;
  // 8 + 9 bytes at 9600 8N1 and two t3.5.
  EXPECT_EQ(transaction_estimate(r, modbus::rtu_timing(9600, false, 1)), 17 * 1042us + 2 * 3646us);
  EXPECT_EQ(transaction_estimate(r, std::nullopt), 1000us);
}

}  // namespace
}  // namespace unima::master
