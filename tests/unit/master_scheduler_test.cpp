// The master's scheduler, driven by simulated time: periods without drift, the line's and
// each device's gaps, earliest due first, retries of reads only, and a dead slave that is
// degraded and probed where it delays nobody.

#include <gtest/gtest.h>

#include <functional>

#include "modbus/master_scheduler.hpp"

namespace unima::modbus {
namespace {

using namespace std::chrono_literals;
using Scheduler = MasterScheduler;
using TimePoint = Scheduler::TimePoint;
using Outcome = Scheduler::Outcome;

const TimePoint t0 = TimePoint{} + 1000s;

PlannedRequest request(std::uint8_t device, std::uint16_t first, std::chrono::milliseconds period, std::uint8_t fn = 3) {
  PlannedRequest r;
  r.device = device;
  r.function = fn;
  r.first = first;
  r.count = 1;
  r.period = period;
  return r;
}

struct Sent {
  TimePoint at;
  std::size_t request;
  unsigned attempt;
  bool probe;
  std::uint8_t device;
};

/// Runs the scheduler until `until`: every choice is sent at once and ends after what
/// `respond` says.
using Respond = std::function<std::pair<Outcome, Scheduler::Duration>(const Scheduler::Choice&, std::uint8_t device)>;
std::vector<Sent> run(Scheduler& s, TimePoint until, const Respond& respond) {
  std::vector<Sent> sent;
  TimePoint now = t0;
  for (int guard = 0; guard < 100000 && now < until; ++guard) {
    const auto decision = s.decide(now);
    if (!decision.send) {
      if (decision.wake == TimePoint::max()) break;
      EXPECT_GT(decision.wake, now) << "woken for nothing";
      now = decision.wake;
      continue;
    }
    const auto& choice = *decision.send;
    const auto device = s.request(choice.request).device;
    sent.push_back({now, choice.request, choice.attempt, choice.probe, device});
    s.begin(choice, now);
    const auto [outcome, duration] = respond(choice, device);
    now += duration;
    s.end(choice, outcome, now);
  }
  return sent;
}

Respond always(Outcome outcome, Scheduler::Duration duration) {
  return [=](const Scheduler::Choice&, std::uint8_t) { return std::make_pair(outcome, duration); };
}

TEST(MasterScheduler, PeriodsDoNotDrift) {
  Scheduler s({request(1, 0, 100ms)}, {}, {}, t0);
  // Each transaction takes 7 ms: the starts stay on the 100 ms grid anyway.
  const auto sent = run(s, t0 + 1s, always(Outcome::answered, 7ms));
  ASSERT_EQ(sent.size(), 10u);
  for (std::size_t k = 0; k < sent.size(); ++k) EXPECT_EQ(sent[k].at, t0 + k * 100ms) << k;
  EXPECT_EQ(s.missed(0), 0u);
}

TEST(MasterScheduler, AnOccurrenceMoreThanAPeriodLateIsSkippedNotBunched) {
  Scheduler s({request(1, 0, 100ms)}, {}, {}, t0);
  s.begin({0, 0, false}, t0);
  s.end({0, 0, false}, Outcome::answered, t0 + 250ms);  // a very slow answer
  const auto decision = s.decide(t0 + 250ms);
  ASSERT_TRUE(decision.send);  // occurrence 1 (due at 100 ms) goes now...
  s.begin(*decision.send, t0 + 250ms);
  EXPECT_EQ(s.due(0), t0 + 300ms);  // ...occurrence 2 is skipped, 3 stays on the grid
  EXPECT_EQ(s.missed(0), 1u);
}

TEST(MasterScheduler, FrameGapAfterEveryTransaction) {
  Scheduler::Options options;
  options.frame_gap = 2ms;
  Scheduler s({request(1, 0, 100ms), request(2, 0, 100ms)}, options, {}, t0);
  const auto sent = run(s, t0 + 50ms, always(Outcome::answered, 5ms));
  ASSERT_EQ(sent.size(), 2u);
  EXPECT_EQ(sent[1].at, t0 + 7ms);
}

TEST(MasterScheduler, MinimumGapPerDeviceLetsOtherDevicesGoMeanwhile) {
  // The stepper driver wants 35 ms between frames; device 2 has no such need.
  Scheduler s({request(1, 0, 100ms), request(1, 10, 100ms), request(2, 0, 100ms)}, {},
              {{1, {35ms, 500ms}}}, t0);
  const auto sent = run(s, t0 + 99ms, always(Outcome::answered, 5ms));
  ASSERT_EQ(sent.size(), 3u);
  EXPECT_EQ(sent[0].at, t0);
  EXPECT_EQ(sent[0].device, 1);
  EXPECT_EQ(sent[1].device, 2);
  EXPECT_EQ(sent[1].at, t0 + 5ms);
  EXPECT_EQ(sent[2].device, 1);
  EXPECT_EQ(sent[2].at, t0 + 35ms);
}

TEST(MasterScheduler, EarliestDueFirst) {
  Scheduler s({request(1, 0, 1000ms), request(2, 0, 30ms)}, {}, {}, t0);
  // Both due at t0 (index order); then device 2 three times before device 1 again.
  const auto sent = run(s, t0 + 100ms, always(Outcome::answered, 25ms));
  ASSERT_GE(sent.size(), 4u);
  EXPECT_EQ(sent[0].device, 1);
  EXPECT_EQ(sent[1].device, 2);
  EXPECT_EQ(sent[2].device, 2);
  EXPECT_EQ(sent[3].device, 2);
}

TEST(MasterScheduler, ReadsAreRetriedWritesNever) {
  Scheduler::Options options;
  options.retries = 2;
  options.degrade_after = 100;
  Scheduler s({request(1, 0, 100ms, 3), request(2, 0, 100ms, 6)}, options, {}, t0);
  const auto sent = run(s, t0 + 150ms, always(Outcome::failed, 10ms));
  // t0: read, retry, retry (device 1); write once (device 2); t0+100ms: the same again.
  std::vector<std::pair<std::uint8_t, unsigned>> seen;
  for (const auto& x : sent) seen.emplace_back(x.device, x.attempt);
  const std::vector<std::pair<std::uint8_t, unsigned>> expected{{1, 0}, {1, 1}, {1, 2}, {2, 0},
                                                                 {1, 0}, {1, 1}, {1, 2}, {2, 0}};
  EXPECT_EQ(seen, expected);
  EXPECT_EQ(sent[4].at, t0 + 100ms);
}

TEST(MasterScheduler, ExceptionAnswersAreNotRetried) {
  Scheduler::Options options;
  options.retries = 3;
  Scheduler s({request(1, 0, 100ms)}, options, {}, t0);
  const auto sent = run(s, t0 + 150ms, always(Outcome::answered, 5ms));
  EXPECT_EQ(sent.size(), 2u);
}

TEST(MasterScheduler, ADeadDeviceIsDegradedAndProbedWithBackoff) {
  Scheduler::Options options;
  options.retries = 0;
  options.degrade_after = 3;
  options.backoff = 1s;
  options.backoff_max = 4s;
  Scheduler s({request(1, 0, 100ms)}, options, {{1, {0ms, 200ms}}}, t0);
  const auto sent = run(s, t0 + 20s, always(Outcome::failed, 200ms));
  // Three failures (0, 200, 400 ms: late, so on the grid at 100 ms steps), then probes
  // after 1 s, 2 s, 4 s, 4 s, ...
  ASSERT_GE(sent.size(), 7u);
  EXPECT_FALSE(sent[2].probe);
  EXPECT_TRUE(sent[3].probe);
  const auto end_of_third = sent[2].at + 200ms;
  EXPECT_EQ(sent[3].at, end_of_third + 1s);
  EXPECT_EQ(sent[4].at, sent[3].at + 200ms + 2s);
  EXPECT_EQ(sent[5].at, sent[4].at + 200ms + 4s);
  EXPECT_EQ(sent[6].at, sent[5].at + 200ms + 4s);
  EXPECT_TRUE(s.degraded(1));
  EXPECT_EQ(s.probe_interval(1), 4s);
}

TEST(MasterScheduler, OneAnswerMakesADegradedDeviceHealthy) {
  Scheduler::Options options;
  options.retries = 0;
  options.degrade_after = 1;
  Scheduler s({request(1, 0, 100ms)}, options, {}, t0);
  s.begin({0, 0, false}, t0);
  EXPECT_EQ(s.end({0, 0, false}, Outcome::failed, t0 + 10ms), Scheduler::Transition::degraded);
  auto decision = s.decide(t0 + 200ms);
  EXPECT_FALSE(decision.send);
  EXPECT_EQ(decision.wake, t0 + 1010ms);
  decision = s.decide(t0 + 1010ms);
  ASSERT_TRUE(decision.send);
  EXPECT_TRUE(decision.send->probe);
  s.begin(*decision.send, t0 + 1010ms);
  EXPECT_EQ(s.end(*decision.send, Outcome::answered, t0 + 1015ms), Scheduler::Transition::recovered);
  EXPECT_FALSE(s.degraded(1));
  EXPECT_EQ(s.due(0), t0 + 1100ms);  // back on its grid
}

TEST(MasterScheduler, ProbesWaitForAPlaceWhereTheyDelayNobody) {
  Scheduler::Options options;
  options.retries = 0;
  options.degrade_after = 1;
  options.backoff = 1s;
  options.backoff_max = 1s;
  // Device 1 answers in 5 ms every 100 ms; device 2 is dead with a 50 ms time-out.
  Scheduler s({request(1, 0, 100ms), request(2, 0, 100ms)}, options, {{2, {0ms, 50ms}}}, t0);
  const auto sent = run(s, t0 + 10s, [](const Scheduler::Choice&, std::uint8_t device) {
    return device == 1 ? std::make_pair(Outcome::answered, 5ms) : std::make_pair(Outcome::failed, 50ms);
  });
  for (std::size_t k = 0, n = 0; k < sent.size(); ++k) {
    if (sent[k].device != 1) continue;
    EXPECT_EQ(sent[k].at, t0 + n * 100ms) << "device 1 delayed at its occurrence " << n;
    ++n;
  }
  std::size_t probes = 0;
  for (const auto& x : sent) probes += x.probe;
  EXPECT_GE(probes, 8u);
}

TEST(MasterScheduler, AProbeThatNeverFindsAPlaceGoesAfterAWholeInterval) {
  Scheduler::Options options;
  options.retries = 0;
  options.degrade_after = 1;
  options.backoff = 1s;
  options.backoff_max = 1s;
  // Device 1 every 20 ms: a 50 ms probe is always in its way.
  Scheduler s({request(1, 0, 20ms), request(2, 0, 100ms)}, options, {{2, {0ms, 50ms}}}, t0);
  const auto sent = run(s, t0 + 5s, [](const Scheduler::Choice&, std::uint8_t device) {
    return device == 1 ? std::make_pair(Outcome::answered, 2ms) : std::make_pair(Outcome::failed, 50ms);
  });
  std::vector<TimePoint> probes;
  for (const auto& x : sent)
    if (x.probe) probes.push_back(x.at);
  ASSERT_GE(probes.size(), 2u);
  EXPECT_LE(probes[1] - probes[0], 2s + 100ms);
}

TEST(MasterScheduler, ReplacedRequestsTakeOverTheSchedule) {
  Scheduler s({request(1, 0, 100ms)}, {}, {}, t0);
  s.begin({0, 0, false}, t0);
  s.end({0, 0, false}, Outcome::answered, t0 + 5ms);
  const auto first = s.replace(0, {request(1, 0, 100ms), request(1, 20, 200ms)});
  EXPECT_FALSE(s.active(0));
  EXPECT_EQ(first, 1u);
  EXPECT_EQ(s.due(1), t0 + 100ms);
  EXPECT_EQ(s.due(2), t0 + 100ms);
  const auto sent = run(s, t0 + 450ms, always(Outcome::answered, 5ms));
  std::size_t old = 0;
  for (const auto& x : sent) old += x.request == 0;
  EXPECT_EQ(old, 0u);
}

}  // namespace
}  // namespace unima::modbus
