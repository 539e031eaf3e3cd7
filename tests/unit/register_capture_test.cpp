// Values seen on the bus for the capture indicators (seed 004 §8): writes from the query
// of functions 6 and 16, reads from the response of 3 and 4, for any address.

#include <gtest/gtest.h>

#include <vector>

#include "monitor/capture_indicators.hpp"
#include "modbus/capture.hpp"
#include "modbus/rtu/crc16.hpp"
#include "modbus/register_capture.hpp"
#include "tests/support/seed_frames.hpp"

namespace unima::modbus {
using namespace unima::monitor;
namespace {

using Bytes = std::vector<std::uint8_t>;
using namespace std::chrono;

const system_clock::time_point t0 = sys_days(year(2026) / November / 22);

Transaction rtu(TransactionState state, const Bytes& query, const Bytes& response) {
  return {PortKind::rtu, {}, t0, state, query, response};
}

TEST(RegisterCapture, AWriteSingleIsCapturedFromTheQuery) {
  const Bytes q = {0x03, 0x06, 0x02, 0x02, 0x12, 0x34, 0x25, 0x27};
  const auto c = captured_registers(rtu(TransactionState::not_for_me, q, {}));  // a foreign slave, unheard
  ASSERT_TRUE(c);
  EXPECT_EQ(c->address, 3);
  EXPECT_EQ(c->access, CaptureAccess::write);
  EXPECT_EQ(c->value_of(0x0202), 0x1234);
  EXPECT_FALSE(c->value_of(0x0203));
}

TEST(RegisterCapture, AWriteMultipleIsCapturedFromTheQuery) {
  const Bytes q = {0x03, 0x10, 0x02, 0x00, 0x00, 0x02, 0x04, 0xAB, 0xCD, 0x12, 0x34, 0x5D, 0xDB};
  const Bytes r = {0x03, 0x10, 0x02, 0x00, 0x00, 0x02, 0x41, 0x92};
  const auto c = captured_registers(rtu(TransactionState::not_for_me, q, r));
  ASSERT_TRUE(c);
  EXPECT_EQ(c->count(), 2u);
  EXPECT_EQ(c->value_of(0x0200), 0xABCD);
  EXPECT_EQ(c->value_of(0x0201), 0x1234);
}

TEST(RegisterCapture, AReadIsCapturedFromTheResponse) {
  const Bytes q = test_support::seed::read_query;
  const Bytes r = test_support::seed::read_response;
  const auto c = captured_registers(rtu(TransactionState::done, q, r));
  ASSERT_TRUE(c);
  EXPECT_EQ(c->access, CaptureAccess::read);
  EXPECT_EQ(c->value_of(0x0011), 0x0050);
  EXPECT_EQ(c->value_of(0x0012), 0x7FFF);
  // Over TCP, the same.
  const Bytes tq = {0x12, 0x34, 0x00, 0x00, 0x00, 0x06, 0x01, 0x04, 0x00, 0x11, 0x00, 0x02};
  const Bytes tr = {0x12, 0x34, 0x00, 0x00, 0x00, 0x07, 0x01, 0x04, 0x04, 0x00, 0x50, 0x7F, 0xFF};
  const auto tc = captured_registers({PortKind::tcp, "127.0.0.1:1", t0, TransactionState::done, tq, tr});
  ASSERT_TRUE(tc);
  EXPECT_EQ(tc->value_of(0x0011), 0x0050);
}

// The capture indicators and capture blocks share this rule: a response from another
// address is not the answer to the query, whatever its bytes (it once counted for indicators).
TEST(RegisterCapture, AReadAnsweredFromAnotherAddressCarriesNothing) {
  const Bytes q = test_support::seed::read_query;
  Bytes r = {0x02, 0x04, 0x04, 0x00, 0x50, 0x7F, 0xFF, 0x00, 0x00};
  const auto crc = crc16(std::span(r).first(r.size() - 2));
  r[r.size() - 2] = static_cast<std::uint8_t>(crc & 0xFF);
  r[r.size() - 1] = static_cast<std::uint8_t>(crc >> 8);
  EXPECT_FALSE(captured_registers(rtu(TransactionState::not_for_me, q, r)));
  const std::vector<CaptureRule> rules{{1, 0x0011, 5}};
  EXPECT_TRUE(captured_reads(rules, q, r).empty());
  r[0] = 0x01;  // the same answer from the queried slave counts for both
  EXPECT_TRUE(captured_registers(rtu(TransactionState::not_for_me, q, r)));
}

TEST(RegisterCapture, NothingFromFaultsExceptionsOrMismatchedAnswers) {
  const Bytes q = test_support::seed::read_query;
  EXPECT_FALSE(captured_registers(rtu(TransactionState::done, q, {})));                               // no answer
  EXPECT_FALSE(captured_registers(rtu(TransactionState::err02, q, {0x01, 0x84, 0x02, 0xC2, 0xC1})));  // exception
  EXPECT_FALSE(captured_registers(rtu(TransactionState::done, q, {0x01, 0x04, 0x02, 0x00, 0x50, 0x00, 0x00})));  // count
  EXPECT_FALSE(captured_registers(rtu(TransactionState::timeout, {0x03, 0x06, 0x02, 0x02, 0x12, 0x34, 0x25, 0x27}, {})));
  EXPECT_FALSE(captured_registers(rtu(TransactionState::err03, {0x03, 0x06, 0x02, 0x02, 0x12, 0x34, 0x00, 0x00}, {})));
  EXPECT_FALSE(captured_registers(rtu(TransactionState::done, {0x01, 0x2B, 0x0E, 0x01, 0x00, 0x70, 0x77}, {})));
}

TEST(CaptureIndicators, KeepTheLastValueReadOrWrittenForTheirAddressAndRegister) {
  CaptureIndicators indicators({{3, 0x0202}, {1, 0x0012}, {1, 0x0300}});
  const Bytes write = {0x03, 0x06, 0x02, 0x02, 0x12, 0x34, 0x25, 0x27};
  const Bytes read_q = test_support::seed::read_query;
  const Bytes read_r = test_support::seed::read_response;
  indicators.observe(*captured_registers(rtu(TransactionState::not_for_me, write, {})), t0);
  indicators.observe(*captured_registers(rtu(TransactionState::done, read_q, read_r)), t0 + seconds(1));
  ASSERT_TRUE(indicators.reading(0));
  EXPECT_EQ(indicators.reading(0)->value, 0x1234);
  EXPECT_EQ(indicators.reading(0)->access, CaptureAccess::write);
  EXPECT_EQ(indicators.reading(0)->time, t0);
  ASSERT_TRUE(indicators.reading(1));
  EXPECT_EQ(indicators.reading(1)->value, 0x7FFF);
  EXPECT_EQ(indicators.reading(1)->access, CaptureAccess::read);
  EXPECT_FALSE(indicators.reading(2));
  // Register 0x0202 of another address does not count.
  const Bytes other = {0x04, 0x06, 0x02, 0x02, 0x00, 0x01, 0x00, 0x00};
  indicators.observe(*captured_registers(rtu(TransactionState::not_for_me, other, {})), t0 + seconds(2));
  EXPECT_EQ(indicators.reading(0)->value, 0x1234);
}

TEST(CaptureIndicators, AReloadKeepsTheReadingsOfUnchangedIndicators) {
  CaptureIndicators old({{3, 0x0202}, {1, 0x0012}});
  old.observe(*captured_registers(rtu(TransactionState::not_for_me, {0x03, 0x06, 0x02, 0x02, 0x12, 0x34, 0x25, 0x27}, {})),
              t0);
  CaptureIndicators fresh({{1, 0x0012}, {3, 0x0202}});
  fresh.take_readings_from(old);
  EXPECT_FALSE(fresh.reading(0));
  ASSERT_TRUE(fresh.reading(1));
  EXPECT_EQ(fresh.reading(1)->value, 0x1234);
}

}  // namespace
}  // namespace unima::modbus
