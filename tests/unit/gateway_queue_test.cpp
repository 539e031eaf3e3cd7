// The gateway's queue (SPEC §14): priority peers first, other clients one request each per
// round, polls and forwarded requests taking turns, and requests that waited too long
// leaving with "busy"; driven by simulated time.

#include <gtest/gtest.h>

#include <vector>

#include "master/gateway_queue.hpp"
#include "master/master_codec.hpp"
#include "master/master_scheduler.hpp"

namespace unima::master {
namespace {

using namespace std::chrono_literals;
using TimePoint = GatewayQueue::TimePoint;

const TimePoint t0 = TimePoint{} + 1000s;

// Client (a connection) `client` of one host, unless another is named.
GatewayQueue::Asker asker(std::uint64_t client, bool priority = false, std::string host = "192.0.2.1") {
  return GatewayQueue::Asker{client, std::move(host), priority};
}

// Takes requests as the line would, with no poll due, and says whose they were.
std::vector<std::uint64_t> serve_all(GatewayQueue& queue) {
  std::vector<std::uint64_t> clients;
  while (const auto next = queue.next(false)) {
    clients.push_back(next->client);
    queue.began(next->ticket);
  }
  return clients;
}

TEST(GatewayQueue, EmptyHasNothingAndNoExpiry) {
  GatewayQueue queue(2s);
  EXPECT_FALSE(queue.next(false));
  EXPECT_FALSE(queue.next(true));
  EXPECT_FALSE(queue.next_expiry());
}

TEST(GatewayQueue, ClientsTakeTurnsOneRequestEachPerRound) {
  GatewayQueue queue(2s);
  // Client 1 sends three before clients 2 and 3 send one each.
  for (int i = 0; i < 3; ++i) queue.push(asker(1, false), 3, t0);
  queue.push(asker(2, false), 3, t0 + 1ms);
  queue.push(asker(3, false), 4, t0 + 2ms);
  EXPECT_EQ(serve_all(queue), (std::vector<std::uint64_t>{1, 2, 3, 1, 1}));
}

TEST(GatewayQueue, TheRoundGoesOnAfterTheClientServedLast) {
  GatewayQueue queue(2s);
  queue.push(asker(2, false), 3, t0);
  queue.began(queue.next(false)->ticket);
  // Client 1 came first this time, but 2 was served last: 3 is next, then 1, then 2.
  queue.push(asker(1, false), 3, t0 + 1ms);
  queue.push(asker(2, false), 3, t0 + 2ms);
  queue.push(asker(3, false), 3, t0 + 3ms);
  EXPECT_EQ(serve_all(queue), (std::vector<std::uint64_t>{3, 1, 2}));
}

TEST(GatewayQueue, PriorityPeersGoFirstEvenBeforeADuePoll) {
  GatewayQueue queue(2s);
  queue.push(asker(1, false), 3, t0);
  queue.push(asker(2, false), 3, t0 + 1ms);
  queue.began(queue.next(false)->ticket);  // client 1: the line's last transaction was forwarded
  queue.push(asker(9, true), 5, t0 + 2ms);
  queue.push(asker(9, true), 6, t0 + 3ms);
  // Now a poll is due, but the priority peer still goes, oldest first.
  auto next = queue.next(true);
  ASSERT_TRUE(next);
  EXPECT_EQ(next->client, 9u);
  EXPECT_EQ(next->unit, 5);
  queue.began(next->ticket);
  next = queue.next(true);
  ASSERT_TRUE(next);
  EXPECT_EQ(next->unit, 6);
  queue.began(next->ticket);
  EXPECT_EQ(serve_all(queue), (std::vector<std::uint64_t>{2}));
}

TEST(GatewayQueue, PriorityRequestsDoNotTakeAnotherClientsTurn) {
  GatewayQueue queue(2s);
  queue.push(asker(1, false), 3, t0);
  queue.push(asker(2, false), 3, t0);
  queue.began(queue.next(false)->ticket);  // client 1
  queue.push(asker(9, true), 3, t0 + 1ms);
  queue.began(queue.next(false)->ticket);  // the priority peer
  EXPECT_EQ(serve_all(queue), (std::vector<std::uint64_t>{2}));
}

TEST(GatewayQueue, ADuePollAndForwardedRequestsTakeTurns) {
  GatewayQueue queue(2s);
  for (int i = 0; i < 4; ++i) queue.push(asker(1, false), 3, t0);
  // At first the line's last user counts as a poll: the request may go even with a poll due.
  auto next = queue.next(true);
  ASSERT_TRUE(next);
  queue.began(next->ticket);
  // A poll is due and the last transaction was forwarded: the poll goes.
  EXPECT_FALSE(queue.next(true));
  queue.poll_began();
  next = queue.next(true);
  ASSERT_TRUE(next);
  queue.began(next->ticket);
  // No poll due: requests may follow each other.
  next = queue.next(false);
  ASSERT_TRUE(next);
  queue.began(next->ticket);
  EXPECT_TRUE(queue.next(false));
  EXPECT_FALSE(queue.next(true));
}

TEST(GatewayQueue, RequestsThatWaitedTooLongLeaveOldestFirst) {
  GatewayQueue queue(2s);
  const auto a = queue.push(asker(1, false), 3, t0);
  const auto b = queue.push(asker(2, false), 3, t0 + 500ms);
  queue.push(asker(3, false), 3, t0 + 1500ms);
  EXPECT_EQ(queue.next_expiry(), t0 + 2s);
  EXPECT_TRUE(queue.expire(t0 + 2s - 1ms).empty());
  const auto expired = queue.expire(t0 + 2500ms);
  ASSERT_EQ(expired.size(), 2u);
  EXPECT_EQ(expired[0].ticket, a);
  EXPECT_EQ(expired[1].ticket, b);
  EXPECT_EQ(queue.size(), 1u);
  EXPECT_EQ(queue.next_expiry(), t0 + 3500ms);
}

TEST(GatewayQueue, AClientThatLeftLeavesNoRequestBehind) {
  GatewayQueue queue(2s);
  queue.push(asker(1, false), 3, t0);
  queue.push(asker(2, false), 3, t0);
  queue.push(asker(1, false), 4, t0);
  EXPECT_EQ(queue.drop_client(1).size(), 2u);
  EXPECT_EQ(serve_all(queue), (std::vector<std::uint64_t>{2}));
}

// Issue 43, finding 5: one host with many connections had most of the line. Hosts take
// turns first, then the connections within a host's turns.
TEST(GatewayQueue, HostsTakeTurnsBeforeTheirConnectionsDo) {
  GatewayQueue queue(2s);
  for (std::uint64_t c = 1; c <= 6; ++c) queue.push(asker(c, false, "192.0.2.1"), 3, t0);
  queue.push(asker(20, false, "192.0.2.9"), 3, t0 + 1ms);
  queue.push(asker(21, false, "192.0.2.9"), 3, t0 + 1ms);
  // 192.0.2.1's six connections get one turn per round, as 192.0.2.9's two do.
  EXPECT_EQ(serve_all(queue), (std::vector<std::uint64_t>{1, 20, 2, 21, 3, 4, 5, 6}));
}

TEST(GatewayQueue, AHostsConnectionsTakeTurnsAcrossRounds) {
  GatewayQueue queue(2s);
  queue.push(asker(1, false, "192.0.2.1"), 3, t0);
  queue.push(asker(2, false, "192.0.2.1"), 3, t0);
  queue.push(asker(9, false, "192.0.2.9"), 3, t0);
  queue.began(queue.next(false)->ticket);  // connection 1
  // Connection 1 asks again at once; its host's next turn is still connection 2's.
  queue.push(asker(1, false, "192.0.2.1"), 3, t0 + 1ms);
  EXPECT_EQ(serve_all(queue), (std::vector<std::uint64_t>{9, 2, 1}));
}

TEST(GatewayQueue, AHostHasAtMostSoManyWaitingAndPriorityPeersAreNotCounted) {
  GatewayQueue queue(2s);
  for (std::uint64_t c = 1; c <= GatewayQueue::most_waiting_per_host; ++c)
    ASSERT_TRUE(queue.push(asker(c, false, "192.0.2.1"), 3, t0));
  EXPECT_FALSE(queue.push(asker(99, false, "192.0.2.1"), 3, t0));  // refused: answered busy
  EXPECT_TRUE(queue.push(asker(100, false, "192.0.2.2"), 3, t0));  // another host still gets in
  EXPECT_TRUE(queue.push(asker(101, true, "192.0.2.1"), 3, t0));   // as does a priority peer
  // One leaving (its turn, its expiry or its connection) frees a place for the host.
  queue.drop_client(1);
  EXPECT_TRUE(queue.push(asker(99, false, "192.0.2.1"), 3, t0 + 1ms));
  EXPECT_FALSE(queue.push(asker(98, false, "192.0.2.1"), 3, t0 + 1ms));
  queue.began(queue.next(false)->ticket);  // the priority peer
  EXPECT_FALSE(queue.push(asker(98, false, "192.0.2.1"), 3, t0 + 1ms));
  queue.began(queue.next(false)->ticket);  // 192.0.2.1's first
  EXPECT_TRUE(queue.push(asker(98, false, "192.0.2.1"), 3, t0 + 1ms));
  EXPECT_EQ(queue.expire(t0 + 3s).size(), GatewayQueue::most_waiting_per_host + 1);
  EXPECT_TRUE(queue.push(asker(97, false, "192.0.2.1"), 3, t0 + 3s));
}

// The scheduler keeps the line's pacing for a transaction that is not its own.
TEST(GatewayLine, AForwardedTransactionHoldsTheLineAndTheDevicesGap) {
  MasterScheduler::Options options;
  options.frame_gap = 2ms;
  PlannedRequest poll;
  poll.device = 3;
  poll.function = 3;
  poll.count = 1;
  poll.period = 1s;
  MasterScheduler scheduler({poll}, options, {{3, MasterScheduler::DeviceTiming{35ms, 500ms}}}, t0);
  EXPECT_EQ(scheduler.ready_for(7), t0);
  scheduler.line_used(3, t0, t0 + 10ms);
  EXPECT_EQ(scheduler.ready_for(7), t0 + 12ms);   // any unit: after the frame gap
  EXPECT_EQ(scheduler.ready_for(3), t0 + 35ms);   // the stepper driver's 35 ms since its last frame
  EXPECT_FALSE(scheduler.decide(t0 + 11ms).send);  // the poll waits for the line too
  EXPECT_EQ(scheduler.decide(t0 + 11ms).wake, t0 + 35ms);
  EXPECT_TRUE(scheduler.knows(3));
  EXPECT_FALSE(scheduler.knows(7));
}

// The queue depth a unit shows in the status: its requests waiting, whoever sent them; a
// request leaves it when it takes the line, expires or its client goes.
TEST(GatewayQueue, EachUnitsWaitingRequestsAreCounted) {
  GatewayQueue queue(2s);
  queue.push(asker(1, false), 5, t0);
  queue.push(asker(2, false), 5, t0);
  queue.push(asker(2, false), 7, t0);
  EXPECT_EQ(queue.waiting_for(5), 2u);
  EXPECT_EQ(queue.waiting_for(7), 1u);
  EXPECT_EQ(queue.waiting_for(9), 0u);
  queue.began(queue.next(false)->ticket);  // client 1's request for 5
  EXPECT_EQ(queue.waiting_for(5), 1u);
  queue.drop_client(2);
  EXPECT_EQ(queue.waiting_for(5), 0u);
  EXPECT_EQ(queue.waiting_for(7), 0u);
}

// A forwarded answer is checked against its request: its frame, then its function or its
// exception, and for the functions the master knows the byte count or the echo; another
// function's answer (43) is taken as it came.
TEST(GatewayCodec, AForwardedAnswerIsCheckedAgainstItsRequest) {
  const Bytes identify{0x2B, 0x0E, 0x01, 0x00};
  const auto answer = rtu_frame(3, Bytes{0x2B, 0x0E, 0x01, 0x01});
  auto r = check_forwarded_rtu_answer(answer, 3, identify);
  EXPECT_EQ(r.status, ResponseStatus::ok);
  EXPECT_EQ(Bytes(r.pdu.begin(), r.pdu.end()), (Bytes{0x2B, 0x0E, 0x01, 0x01}));
  const Bytes read_one{0x03, 0x00, 0xC8, 0x00, 0x01};
  const auto exception = rtu_frame(3, Bytes{0x83, 0x02});
  r = check_forwarded_rtu_answer(exception, 3, read_one);
  EXPECT_EQ(r.status, ResponseStatus::exception);
  EXPECT_EQ(r.exception, modbus::ExceptionCode::illegal_data_address);
  EXPECT_EQ(Bytes(r.pdu.begin(), r.pdu.end()), (Bytes{0x83, 0x02}));
  EXPECT_EQ(check_forwarded_rtu_answer(answer, 4, identify).status, ResponseStatus::wrong_address);
  auto corrupt = answer;
  corrupt.back() ^= 0x01;
  EXPECT_EQ(check_forwarded_rtu_answer(corrupt, 3, identify).status, ResponseStatus::bad_crc);
  EXPECT_EQ(check_forwarded_rtu_answer({}, 3, identify).status, ResponseStatus::timeout);
  EXPECT_EQ(check_forwarded_rtu_answer(Bytes{0x03, 0x83, 0x02}, 3, identify).status, ResponseStatus::too_short);
}

// Issue 43's late answers: a slave past its time-out answers the previous request while
// the next is on the line. An answer of another function, of another length than the
// quantity asked, or echoing another write is not this request's.
TEST(GatewayCodec, AnAnswerToAnotherRequestIsRefused) {
  const Bytes read_one{0x03, 0x00, 0xC8, 0x00, 0x01};
  const Bytes read_ten{0x03, 0x00, 0xC8, 0x00, 0x0A};
  const Bytes write_6{0x06, 0x00, 0xC8, 0x00, 0x06};
  const auto one_register = rtu_frame(3, Bytes{0x03, 0x02, 0x00, 0x2A});
  EXPECT_EQ(check_forwarded_rtu_answer(one_register, 3, read_one).status, ResponseStatus::ok);
  EXPECT_EQ(check_forwarded_rtu_answer(one_register, 3, read_ten).status, ResponseStatus::bad_length);
  EXPECT_EQ(check_forwarded_rtu_answer(one_register, 3, write_6).status, ResponseStatus::wrong_function);
  const auto echo_of_7 = rtu_frame(3, Bytes{0x06, 0x00, 0xC8, 0x00, 0x07});
  EXPECT_EQ(check_forwarded_rtu_answer(echo_of_7, 3, write_6).status, ResponseStatus::wrong_echo);
  EXPECT_EQ(check_forwarded_rtu_answer(rtu_frame(3, write_6), 3, write_6).status, ResponseStatus::ok);
  EXPECT_EQ(check_forwarded_rtu_answer(rtu_frame(3, Bytes{0x84, 0x02}), 3, read_one).status,
            ResponseStatus::wrong_function);
  // A request too short to say its quantity cannot be answered with data.
  EXPECT_EQ(check_forwarded_rtu_answer(one_register, 3, Bytes{0x03, 0x00}).status, ResponseStatus::bad_frame);
}

}  // namespace
}  // namespace unima::master
