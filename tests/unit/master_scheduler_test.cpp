// The master's scheduler, driven by simulated time: periods without drift, the line's and
// each device's gaps, earliest due first, retries of reads only, a dead slave that is
// degraded and probed where it delays nobody, frames to devices in doubt only in the gaps
// of the live ones, and a start-up whose dead slave costs one longer first interval.

#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <map>

#include "master/master_scheduler.hpp"

namespace unima::master {
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
  Scheduler::Duration wait;  // how long the scheduler let it wait for an answer
};

/// Runs the scheduler until `until`: every choice is sent at once and ends after what
/// `respond` says; a failure no later than the wait the scheduler chose (the link's
/// deadline).
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
    sent.push_back({now, choice.request, choice.attempt, choice.probe, device, choice.timeout});
    s.begin(choice, now);
    auto [outcome, duration] = respond(choice, device);
    if (outcome == Outcome::failed && choice.timeout > Scheduler::Duration::zero())
      duration = std::min(duration, choice.timeout);
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

// Issue 43: after a time-out the line is quiet for as long again, for every device, so that
// a slave later than its time-out answers into silence, not into the next transaction.
TEST(MasterScheduler, AfterATimeOutTheLineIsQuietAsLongAgain) {
  Scheduler::Options options;
  options.frame_gap = 2ms;
  Scheduler s({request(1, 0, 100ms), request(2, 0, 100ms)}, options, {}, t0);
  s.line_used(9, t0, t0 + 300ms);
  EXPECT_EQ(s.ready_for(2), t0 + 302ms);
  s.timed_out(t0 + 300ms, 300ms);
  EXPECT_EQ(s.ready_for(2), t0 + 600ms);
  EXPECT_EQ(s.ready_for(9), t0 + 600ms);
  s.timed_out(t0 + 300ms, 10ms);  // a shorter wait never shortens the quiet
  EXPECT_EQ(s.ready_for(2), t0 + 600ms);
  s.timed_out(t0 + 1s, 1500ms);  // a long time-out: quiet for longest_quiet
  EXPECT_EQ(s.ready_for(2), t0 + 1s + Scheduler::longest_quiet);
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

TEST(MasterScheduler, ALineBackProbesEveryDegradedDeviceAtOnceWithItsBackoffAnew) {
  Scheduler::Options options;
  options.retries = 0;
  options.degrade_after = 1;
  options.backoff = 1s;
  options.backoff_max = 30s;
  Scheduler s({request(1, 0, 100ms)}, options, {}, t0);
  const auto sent = run(s, t0 + 60s, always(Outcome::failed, 10ms));
  ASSERT_TRUE(s.degraded(1));
  EXPECT_EQ(s.probe_interval(1), 30s) << "the probes on the lost line have backed off";
  const auto back = sent.back().at + 1s;
  EXPECT_FALSE(s.decide(back).send) << "without line_back, the next probe is up to 30 s away";
  s.line_back(back);
  const auto decision = s.decide(back);
  ASSERT_TRUE(decision.send);
  EXPECT_TRUE(decision.send->probe);
  s.begin(*decision.send, back);
  EXPECT_EQ(s.end(*decision.send, Outcome::failed, back + 10ms), Scheduler::Transition::none);
  EXPECT_EQ(s.probe_interval(1), 2s) << "the backoff starts again";
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

// --- Frames to devices in doubt go only where they delay no live request ---------------

/// One transaction by hand: `choice` goes at `at` and ends `after` later.
Scheduler::Transition transact(Scheduler& s, const Scheduler::Choice& choice, TimePoint at, Outcome outcome,
                               Scheduler::Duration after) {
  s.begin(choice, at);
  return s.end(choice, outcome, at + after);
}

PlannedRequest phased(PlannedRequest r, std::chrono::milliseconds phase) {
  r.phase = phase;
  return r;
}

Scheduler::Options doubt_options() {
  Scheduler::Options options;
  options.retries = 0;
  options.degrade_after = 1;
  options.backoff = 1s;
  options.backoff_max = 1s;
  options.guard = 2ms;
  return options;
}

TEST(MasterScheduler, AProbeIsDeferredWhenItWouldDelayALiveRequestAndGoesInTheNextGap) {
  // Device 1 (live) every 100 ms from +50 ms, 5 ms a transaction; device 2 has a 100 ms
  // time-out, answers garbage once and is degraded: its probe falls due 35 ms before
  // device 1's next request.
  Scheduler s({phased(request(1, 0, 100ms), 50ms), request(2, 0, 1000ms)}, doubt_options(), {{2, {0ms, 100ms}}}, t0);
  auto d = s.decide(t0);
  ASSERT_TRUE(d.send);
  ASSERT_EQ(d.send->request, 1u);
  EXPECT_EQ(transact(s, *d.send, t0, Outcome::failed, 15ms), Scheduler::Transition::degraded);
  for (auto at = t0 + 50ms; at <= t0 + 950ms; at += 100ms) {
    d = s.decide(at);
    ASSERT_TRUE(d.send && d.send->request == 0) << (at - t0).count();
    transact(s, *d.send, at, Outcome::answered, 5ms);
  }
  EXPECT_TRUE(s.live(1));
  // The probe is due at 1015 ms; device 1 at 1050 ms: 35 ms is less than half the time-out.
  d = s.decide(t0 + 1015ms);
  EXPECT_FALSE(d.send);
  EXPECT_EQ(d.wake, t0 + 1050ms);
  d = s.decide(t0 + 1050ms);
  ASSERT_TRUE(d.send);
  EXPECT_EQ(d.send->request, 0u) << "the live request goes first";
  transact(s, *d.send, t0 + 1050ms, Outcome::answered, 5ms);
  // After it, 95 ms until the next: the probe waits 93 ms (2 ms guard), not its whole 100 ms.
  d = s.decide(t0 + 1055ms);
  ASSERT_TRUE(d.send);
  EXPECT_TRUE(d.send->probe);
  EXPECT_EQ(d.send->timeout, 93ms);
  transact(s, *d.send, t0 + 1055ms, Outcome::failed, d.send->timeout);
  d = s.decide(t0 + 1150ms);
  ASSERT_TRUE(d.send);
  EXPECT_EQ(d.send->request, 0u) << "device 1 on time";
}

TEST(MasterScheduler, AProbeWaitsItsWholeTimeOutWhereTheGapIsLongEnough) {
  Scheduler::Options options = doubt_options();
  options.char_time = 260us;  // 38400 baud: the probe's 8-byte frame takes 2.08 ms
  options.frame_gap = 1750us;
  // Device 1 every 500 ms: mostly room for a 100 ms time-out, sometimes only for part of it.
  Scheduler s({request(1, 0, 500ms), phased(request(2, 0, 1000ms), 100ms)}, options, {{2, {0ms, 100ms}}}, t0);
  const auto sent = run(s, t0 + 20s, [](const Scheduler::Choice&, std::uint8_t device) {
    return device == 1 ? std::make_pair(Outcome::answered, 6ms) : std::make_pair(Outcome::failed, 200ms);
  });
  std::size_t full = 0, cut = 0;
  for (std::size_t k = 0; k < sent.size(); ++k) {
    if (!sent[k].probe) continue;
    const auto next = std::find_if(sent.begin() + static_cast<std::ptrdiff_t>(k), sent.end(),
                                   [](const Sent& x) { return x.device == 1; });
    if (next == sent.end()) break;  // the run ended first
    const auto room = next->at - sent[k].at - 2080us - 1750us - 2ms;
    if (room >= 100ms) {
      EXPECT_EQ(sent[k].wait, 100ms) << "probe at " << (sent[k].at - t0).count();
      ++full;
    } else {
      EXPECT_LE(sent[k].wait, room);
      EXPECT_GE(sent[k].wait, 50ms);
      ++cut;
    }
  }
  EXPECT_GE(full, 10u);
  EXPECT_GE(full + cut, 15u);
}

TEST(MasterScheduler, AFrameInDoubtNeverWaitsLessThanHalfItsTimeOutNorLessThanTheDeviceTookToAnswer) {
  // Device 2 answered once in 70 ms, then failed: its next frame needs room for 87.5 ms
  // (70 ms and a quarter), though half its time-out is 50 ms.
  Scheduler::Options options = doubt_options();
  options.degrade_after = 5;
  Scheduler s({request(1, 0, 100ms), phased(request(2, 0, 100ms), 10ms)}, options, {{2, {0ms, 100ms}}}, t0);
  auto d = s.decide(t0);
  transact(s, *d.send, t0, Outcome::answered, 5ms);
  d = s.decide(t0 + 10ms);
  ASSERT_EQ(d.send->request, 1u);
  transact(s, *d.send, t0 + 10ms, Outcome::answered, 70ms);  // the slowest answer: 70 ms
  d = s.decide(t0 + 100ms);
  ASSERT_EQ(d.send->request, 0u);
  transact(s, *d.send, t0 + 100ms, Outcome::answered, 5ms);
  d = s.decide(t0 + 110ms);
  ASSERT_EQ(d.send->request, 1u);
  transact(s, *d.send, t0 + 110ms, Outcome::failed, 100ms);  // no answer: device 2 is in doubt
  EXPECT_FALSE(s.live(2));
  d = s.decide(t0 + 210ms);  // device 1 was due at 200 ms
  ASSERT_EQ(d.send->request, 0u);
  transact(s, *d.send, t0 + 210ms, Outcome::answered, 5ms);
  // 85 ms to device 1's next request (300 ms) minus the guard: 83 ms, short of 87.5 ms.
  d = s.decide(t0 + 215ms);
  EXPECT_FALSE(d.send) << "a frame shorter than the device's slowest answer would learn nothing";
  EXPECT_EQ(d.wake, t0 + 300ms);
}

TEST(MasterScheduler, ADeadDeviceIsStillProbedWithinABoundedTimeWhenTheLineHasGaps) {
  Scheduler::Options options = doubt_options();
  options.retries = 1;
  options.degrade_after = 3;
  options.backoff_max = 4s;
  options.char_time = 260us;
  options.frame_gap = 1750us;
  // The benchmark's shape: 100, 200 and 250 ms requests of live devices, 6 ms each, and a
  // dead device with a 100 ms time-out that never fits whole between them.
  std::vector<PlannedRequest> plan{request(1, 0, 100ms), phased(request(1, 10, 200ms), 20ms),
                                   phased(request(1, 20, 250ms), 40ms), phased(request(3, 0, 200ms), 30ms),
                                   phased(request(2, 0, 100ms), 10ms), phased(request(2, 10, 500ms), 50ms)};
  Scheduler s(std::move(plan), options, {{2, {10ms, 100ms}}}, t0);
  const auto sent = run(s, t0 + 60s, [](const Scheduler::Choice&, std::uint8_t device) {
    return device == 2 ? std::make_pair(Outcome::failed, 100ms) : std::make_pair(Outcome::answered, 6ms);
  });
  ASSERT_TRUE(s.degraded(2));
  std::map<std::size_t, std::vector<TimePoint>> starts;
  std::vector<TimePoint> dead;
  for (const auto& x : sent) {
    if (x.device == 2) dead.push_back(x.at);
    else starts[x.request].push_back(x.at);
  }
  // Every live request keeps its period exactly, after its first interval.
  for (const auto& [index, times] : starts) {
    ASSERT_GE(times.size(), 3u);
    for (std::size_t k = 2; k < times.size(); ++k)
      EXPECT_EQ(times[k] - times[k - 1], s.request(index).period) << "request " << index << " occurrence " << k;
  }
  // The dead device: its probes keep coming, never further apart than the longest probe
  // interval plus the time-out and one wait for a gap.
  ASSERT_GE(dead.size(), 15u);
  for (std::size_t k = 1; k < dead.size(); ++k) EXPECT_LE(dead[k] - dead[k - 1], 4s + 100ms + 100ms) << k;
}

TEST(MasterScheduler, ARetryWaitsForAGapAndGivesWayToItsRequestsNextOccurrence) {
  Scheduler::Options options = doubt_options();
  options.retries = 1;
  options.degrade_after = 10;
  // Device 1 (live) every 100 ms; device 2 every 100 ms from +50 ms, time-out 100 ms.
  Scheduler s({request(1, 0, 100ms), phased(request(2, 0, 100ms), 50ms)}, options, {{2, {0ms, 100ms}}}, t0);
  auto d = s.decide(t0);
  transact(s, *d.send, t0, Outcome::answered, 5ms);
  d = s.decide(t0 + 50ms);
  ASSERT_EQ(d.send->request, 1u);
  transact(s, *d.send, t0 + 50ms, Outcome::answered, 5ms);
  d = s.decide(t0 + 100ms);
  transact(s, *d.send, t0 + 100ms, Outcome::answered, 5ms);
  d = s.decide(t0 + 150ms);
  ASSERT_EQ(d.send->request, 1u);
  transact(s, *d.send, t0 + 150ms, Outcome::failed, 10ms);  // garbage: a retry is owed
  // 40 ms to device 1's request: too short for a retry that may wait 100 ms.
  d = s.decide(t0 + 160ms);
  EXPECT_FALSE(d.send);
  EXPECT_EQ(d.wake, t0 + 200ms);
  d = s.decide(t0 + 200ms);
  ASSERT_EQ(d.send->request, 0u);
  transact(s, *d.send, t0 + 200ms, Outcome::answered, 49ms);  // a slow answer: 49 ms of room left
  d = s.decide(t0 + 249ms);
  EXPECT_FALSE(d.send) << "49 ms is less than half the time-out";
  // The retry's request is due again: the retry gives way to it, which does not fit either.
  d = s.decide(t0 + 250ms);
  EXPECT_FALSE(d.send);
  d = s.decide(t0 + 300ms);
  ASSERT_EQ(d.send->request, 0u);
  transact(s, *d.send, t0 + 300ms, Outcome::answered, 5ms);
  d = s.decide(t0 + 305ms);
  ASSERT_TRUE(d.send);
  EXPECT_EQ(d.send->request, 1u);
  EXPECT_EQ(d.send->attempt, 0u) << "the occurrence, not the stale retry";
  EXPECT_EQ(d.send->timeout, 93ms);
  transact(s, *d.send, t0 + 305ms, Outcome::failed, 10ms);
  // Now the retry fits at once: 85 ms to device 1's next request, less the guard.
  d = s.decide(t0 + 315ms);
  ASSERT_TRUE(d.send);
  EXPECT_EQ(d.send->request, 1u);
  EXPECT_EQ(d.send->attempt, 1u);
  EXPECT_EQ(d.send->timeout, 83ms);
}

TEST(MasterScheduler, AFailedFirstContactMovesTheLiveScheduleByWholeDivisorsOfThePeriods) {
  // Device 1 answers at once; device 2 (never heard yet) holds the line 100 ms at +10 ms.
  Scheduler s({request(1, 0, 100ms), phased(request(1, 20, 250ms), 40ms), phased(request(2, 0, 500ms), 10ms)},
              doubt_options(), {{2, {0ms, 100ms}}}, t0);
  auto d = s.decide(t0);
  transact(s, *d.send, t0, Outcome::answered, 5ms);
  d = s.decide(t0 + 10ms);
  ASSERT_EQ(d.send->request, 2u);
  EXPECT_EQ(d.send->timeout, 100ms) << "a device never heard from is presumed alive";
  transact(s, *d.send, t0 + 10ms, Outcome::failed, 100ms);
  // Device 1's requests were due at 100 and 40 ms; the line was busy until 110 ms. The
  // periods' divisor is 50 ms: both move by 100 ms, and stay 60 ms apart on their circle.
  EXPECT_EQ(s.due(0), t0 + 200ms);
  EXPECT_EQ(s.due(1), t0 + 140ms);
  // A device's later failures move nothing.
  d = s.decide(t0 + 140ms);
  ASSERT_EQ(d.send->request, 1u);
  transact(s, *d.send, t0 + 140ms, Outcome::answered, 5ms);
  EXPECT_EQ(s.due(0), t0 + 200ms);
}

TEST(MasterScheduler, AFirstContactThatAnswersMovesNothing) {
  Scheduler s({request(1, 0, 100ms), phased(request(2, 0, 100ms), 10ms)}, doubt_options(), {}, t0);
  auto d = s.decide(t0);
  transact(s, *d.send, t0, Outcome::answered, 5ms);
  d = s.decide(t0 + 10ms);
  transact(s, *d.send, t0 + 10ms, Outcome::answered, 95ms);  // slow, but an answer
  EXPECT_EQ(s.due(0), t0 + 100ms);
}

TEST(MasterScheduler, ADeviceThatAnswersAgainResumesItsGridWithoutABurst) {
  Scheduler::Options options = doubt_options();
  Scheduler s({request(1, 0, 100ms), request(1, 10, 300ms)}, options, {{1, {0ms, 50ms}}}, t0);
  auto d = s.decide(t0);
  EXPECT_EQ(transact(s, *d.send, t0, Outcome::failed, 50ms), Scheduler::Transition::degraded);
  d = s.decide(t0 + 1050ms);
  ASSERT_TRUE(d.send && d.send->probe);
  EXPECT_EQ(transact(s, *d.send, t0 + 1050ms, Outcome::answered, 5ms), Scheduler::Transition::recovered);
  // The 300 ms request was due at 0 ms: it goes at its next point of its grid, 1200 ms,
  // not at once; the probed one at 1100 ms.
  EXPECT_EQ(s.due(1), t0 + 1200ms);
  EXPECT_EQ(s.due(0), t0 + 1100ms);
  d = s.decide(t0 + 1055ms);
  EXPECT_FALSE(d.send);
  EXPECT_EQ(d.wake, t0 + 1100ms);
}

}  // namespace
}  // namespace unima::master
