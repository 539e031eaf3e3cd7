// The gateway's decisions (master/gateway, SPEC §14) driven by time points and frames,
// without a line: a request's way from arrival through the queue and the line to its
// answer, the time-out it is given, what each outcome counts as, the cache's part, and
// the gateway's own exception answers.

#include <gtest/gtest.h>

#include "master/gateway.hpp"

namespace unima::master {
namespace {

using namespace std::chrono_literals;
using TimePoint = Gateway::TimePoint;
using Sent = std::chrono::system_clock::time_point;

const TimePoint t0 = TimePoint{} + 1000s;
const Sent sent0 = Sent{} + 1000s;
const Bytes read_d0{0x03, 0x00, 0x00, 0x00, 0x01};
const Bytes write_d0{0x06, 0x00, 0x00, 0x00, 0x2A};
constexpr std::uint8_t plc = 5;

GatewayQueue::Asker asker(std::uint64_t client, bool priority = false) {
  return GatewayQueue::Asker{client, "192.0.2.1", priority};
}

Gateway::Settings settings(std::chrono::milliseconds cache = 0ms) {
  return Gateway::Settings{300ms, std::nullopt, cache};
}

// A request that arrives and takes the line at once; its ticket.
GatewayQueue::Request take_line(Gateway& gateway, std::uint64_t client, const Bytes& pdu, TimePoint now) {
  const auto arrival = gateway.arrive(asker(client), plc, pdu, now);
  EXPECT_FALSE(arrival.cached);
  const auto next = gateway.next(false);
  EXPECT_TRUE(next);
  EXPECT_EQ(next->ticket, arrival.ticket);
  gateway.began(*next, pdu, now);
  return *next;
}

TEST(GatewayDecisions, TheSlavesDataGoesBackAsItCameAndIsCounted) {
  Gateway gateway(settings());
  take_line(gateway, 1, read_d0, t0);
  const auto outcome = gateway.finished(plc, read_d0, rtu_frame(plc, Bytes{0x03, 0x02, 0x12, 0x34}), t0 + 20ms, sent0);
  EXPECT_EQ(outcome.answer, (Bytes{0x03, 0x02, 0x12, 0x34}));
  EXPECT_EQ(outcome.result.status, ResponseStatus::ok);
  const auto& counters = gateway.units().at(plc);
  EXPECT_EQ(counters.requests, 1u);
  EXPECT_EQ(counters.answered, 1u);
  EXPECT_EQ(counters.timeouts + counters.bad_frames + counters.exceptions, 0u);
}

TEST(GatewayDecisions, TheSlavesOwnExceptionIsAnAnswerAndGoesBackAsItCame) {
  Gateway gateway(settings());
  take_line(gateway, 1, read_d0, t0);
  const auto outcome = gateway.finished(plc, read_d0, rtu_frame(plc, Bytes{0x83, 0x02}), t0 + 20ms, sent0);
  EXPECT_EQ(outcome.answer, (Bytes{0x83, 0x02}));
  EXPECT_EQ(gateway.units().at(plc).exceptions, 1u);
  EXPECT_TRUE(gateway.units().at(plc).answering.answering());
}

TEST(GatewayDecisions, NoAnswerABadCrcOrAnotherSlavesAnswerIs0BAndThreeInARowAreSilence) {
  Gateway gateway(settings());
  auto bad_crc = rtu_frame(plc, Bytes{0x03, 0x02, 0x12, 0x34});
  bad_crc.back() ^= 0xFF;
  const std::vector<Bytes> failures{Bytes{}, bad_crc, rtu_frame(plc + 1, Bytes{0x03, 0x02, 0x12, 0x34})};
  std::vector<UnitAnswering::Transition> transitions;
  for (const auto& frame : failures) {
    take_line(gateway, 1, read_d0, t0);
    const auto outcome = gateway.finished(plc, read_d0, frame, t0 + 300ms, sent0);
    EXPECT_EQ(outcome.answer, (Bytes{0x83, 0x0B}));
    transitions.push_back(outcome.transition);
  }
  EXPECT_EQ(transitions.back(), UnitAnswering::Transition::stopped_answering);
  EXPECT_EQ(transitions.front(), UnitAnswering::Transition::none);
  const auto& counters = gateway.units().at(plc);
  EXPECT_EQ(counters.timeouts, 1u);
  EXPECT_EQ(counters.bad_frames, 2u);
  take_line(gateway, 1, read_d0, t0 + 1s);
  EXPECT_EQ(gateway.finished(plc, read_d0, rtu_frame(plc, Bytes{0x03, 0x02, 0, 1}), t0 + 1s, sent0).transition,
            UnitAnswering::Transition::answers_again);
}

TEST(GatewayDecisions, ARequestThatWaitedTooLongIsCountedBusy) {
  Gateway gateway(settings());
  const auto first = gateway.arrive(asker(1), plc, read_d0, t0).ticket;
  gateway.arrive(asker(2), plc, read_d0, t0 + 100ms);
  EXPECT_EQ(gateway.next_expiry(), t0 + 300ms);
  EXPECT_TRUE(gateway.expire(t0 + 299ms).empty());
  const auto expired = gateway.expire(t0 + 300ms);
  ASSERT_EQ(expired.size(), 1u);
  EXPECT_EQ(expired.front().ticket, first);
  EXPECT_EQ(gateway.units().at(plc).busy, 1u);
  EXPECT_EQ(gateway.queue_depth(plc), 1u);
  EXPECT_EQ(gateway_exception(0x03, modbus::ExceptionCode::server_device_busy), (Bytes{0x83, 0x06}));
}

TEST(GatewayDecisions, ARequestBeyondItsHostsShareIsRefusedAtOnceAndCountedBusy) {
  Gateway gateway(settings());
  for (std::uint64_t c = 1; c <= GatewayQueue::most_waiting_per_host; ++c)
    ASSERT_TRUE(gateway.arrive(asker(c), plc, read_d0, t0).ticket);
  const auto refused = gateway.arrive(asker(99), plc, read_d0, t0);
  EXPECT_FALSE(refused.ticket);
  EXPECT_FALSE(refused.cached);
  EXPECT_EQ(gateway.units().at(plc).busy, 1u);
  EXPECT_EQ(gateway.queue_depth(plc), GatewayQueue::most_waiting_per_host);
}

TEST(GatewayDecisions, TheWaitForTheLineIsMeasuredFromArrival) {
  Gateway gateway(settings());
  gateway.arrive(asker(1), plc, read_d0, t0);
  gateway.began(*gateway.next(false), read_d0, t0 + 40ms);
  EXPECT_EQ(gateway.units().at(plc).wait.last(), 40ms);
  EXPECT_EQ(gateway.waiting(), 0u);
}

TEST(GatewayDecisions, AClientThatWentTakesItsQueuedRequestsWithIt) {
  Gateway gateway(settings());
  const auto a = gateway.arrive(asker(1), plc, read_d0, t0).ticket.value();
  gateway.arrive(asker(2), plc, read_d0, t0);
  const auto b = gateway.arrive(asker(1), plc, write_d0, t0).ticket.value();
  EXPECT_EQ(gateway.client_gone(1), (std::vector<Gateway::Ticket>{a, b}));
  EXPECT_EQ(gateway.waiting(), 1u);
}

TEST(GatewayDecisions, TheTimeOutIsTheGatewaysElseTheDevicesElseOneSecond) {
  EXPECT_EQ(Gateway(Gateway::Settings{300ms, 150ms, 0ms}).timeout(500ms), 150ms);
  EXPECT_EQ(Gateway(settings()).timeout(500ms), 500ms);
  EXPECT_EQ(Gateway(settings()).timeout(std::nullopt), 1000ms);
}

TEST(GatewayDecisions, TheCacheAnswersAnEqualReadAndAnyWriteEmptiesIt) {
  Gateway gateway(settings(500ms));
  take_line(gateway, 1, read_d0, t0);
  gateway.finished(plc, read_d0, rtu_frame(plc, Bytes{0x03, 0x02, 0x00, 0x07}), t0 + 10ms, sent0);
  const auto hit = gateway.arrive(asker(2), plc, read_d0, t0 + 100ms);
  ASSERT_TRUE(hit.cached);
  EXPECT_EQ(*hit.cached, (Bytes{0x03, 0x02, 0x00, 0x07}));
  EXPECT_EQ(gateway.units().at(plc).cache_hits, 1u);
  EXPECT_EQ(gateway.waiting(), 0u) << "a cached answer takes no turn";

  gateway.device_written(plc);  // the master's own send block
  EXPECT_FALSE(gateway.arrive(asker(2), plc, read_d0, t0 + 200ms).cached);
}

TEST(GatewayDecisions, AReadAnsweredWhileAWriteWaitedIsForgottenWhenTheWriteTakesTheLine) {
  Gateway gateway(settings(500ms));
  const auto write = gateway.arrive(asker(1), plc, write_d0, t0);
  EXPECT_FALSE(write.cached);
  // The write waits; a read of another client goes first and is answered and kept.
  const auto read = gateway.arrive(asker(2, true), plc, read_d0, t0);
  const auto next = gateway.next(false);
  ASSERT_TRUE(next);
  ASSERT_EQ(next->ticket, read.ticket);
  gateway.began(*next, read_d0, t0);
  gateway.finished(plc, read_d0, rtu_frame(plc, Bytes{0x03, 0x02, 0x00, 0x07}), t0 + 10ms, sent0);
  EXPECT_TRUE(gateway.arrive(asker(3), plc, read_d0, t0 + 20ms).cached);
  gateway.began(*gateway.next(false), write_d0, t0 + 30ms);
  EXPECT_FALSE(gateway.arrive(asker(3), plc, read_d0, t0 + 40ms).cached);
}

TEST(GatewayDecisions, AnExceptionIsNeverCached) {
  Gateway gateway(settings(500ms));
  take_line(gateway, 1, read_d0, t0);
  gateway.finished(plc, read_d0, rtu_frame(plc, Bytes{0x83, 0x02}), t0 + 10ms, sent0);
  EXPECT_FALSE(gateway.arrive(asker(2), plc, read_d0, t0 + 20ms).cached);
}

// Issue 43: an answer that is not this request's — a late slave's answer to the request
// before — is 0x0B to this client and never kept; and the transaction after a time-out is
// not kept either (what came on the line then may have been the late answer).
TEST(GatewayDecisions, ALateAnswerToAnotherRequestIs0BAndNeverCached) {
  Gateway gateway(settings(500ms));
  const Bytes read_ten{0x03, 0x00, 0xC8, 0x00, 0x0A};
  take_line(gateway, 1, read_ten, t0);
  const auto outcome = gateway.finished(plc, read_ten, rtu_frame(plc, Bytes{0x03, 0x02, 0x00, 0x07}), t0 + 10ms, sent0);
  EXPECT_EQ(outcome.answer, (Bytes{0x83, 0x0B}));
  EXPECT_EQ(outcome.result.status, ResponseStatus::bad_length);
  EXPECT_EQ(gateway.units().at(plc).bad_frames, 1u);
  EXPECT_FALSE(gateway.arrive(asker(2), plc, read_ten, t0 + 20ms).cached);
}

TEST(GatewayDecisions, TheTransactionAfterATimeOutIsNotCached) {
  Gateway gateway(settings(500ms));
  const auto answer = rtu_frame(plc, Bytes{0x03, 0x02, 0x00, 0x07});
  // Another client's equal read: answered from the cache, or else it leaves the queue.
  const auto cached = [&](TimePoint at) {
    const bool hit = gateway.arrive(asker(2), plc, read_d0, at).cached.has_value();
    gateway.client_gone(2);
    return hit;
  };
  take_line(gateway, 1, read_d0, t0);
  gateway.finished(plc, read_d0, Bytes{}, t0 + 300ms, sent0);  // no answer
  take_line(gateway, 1, read_d0, t0 + 600ms);
  EXPECT_EQ(gateway.finished(plc, read_d0, answer, t0 + 610ms, sent0).answer, (Bytes{0x03, 0x02, 0x00, 0x07}));
  EXPECT_FALSE(cached(t0 + 620ms)) << "after a time-out";
  // A poll that timed out counts as well; one that was answered clears it.
  gateway.poll_ended(true);
  take_line(gateway, 1, read_d0, t0 + 1s);
  gateway.finished(plc, read_d0, answer, t0 + 1s, sent0);
  EXPECT_FALSE(cached(t0 + 1s));
  gateway.poll_ended(false);
  take_line(gateway, 1, read_d0, t0 + 2s);
  gateway.finished(plc, read_d0, answer, t0 + 2s, sent0);
  EXPECT_TRUE(cached(t0 + 2s));
}

}  // namespace
}  // namespace unima::master
