// modbus::serve_request and recipient_of: whose request it is on TCP and on RTU, what is
// answered, the state the monitor logs and what counts as a fault — the same for both ports.

#include <gtest/gtest.h>

#include <array>
#include <vector>

#include "modbus/slave_session.hpp"
#include "modbus/write_rights.hpp"
#include "tests/support/map_registers.hpp"

namespace unima::modbus {
namespace {

using test_support::MapRegisters;
using Bytes = std::vector<std::uint8_t>;

TEST(SlaveSession, WhoseRequestItIsByLink) {
  EXPECT_EQ(recipient_of(Link::tcp, 7, 7), Recipient::this_slave);
  EXPECT_EQ(recipient_of(Link::tcp, 0, 7), Recipient::this_slave);    // unit id "any"
  EXPECT_EQ(recipient_of(Link::tcp, 255, 7), Recipient::this_slave);  // unit id "not used"
  EXPECT_EQ(recipient_of(Link::tcp, 8, 7), Recipient::another_slave);
  EXPECT_EQ(recipient_of(Link::rtu, 7, 7), Recipient::this_slave);
  EXPECT_EQ(recipient_of(Link::rtu, 0, 7), Recipient::broadcast);
  EXPECT_EQ(recipient_of(Link::rtu, 255, 7), Recipient::another_slave);
  EXPECT_EQ(recipient_of(Link::rtu, 8, 7), Recipient::another_slave);
}

struct SlaveSessionServing : ::testing::Test {
  MapRegisters registers{{{0x0011, 0x1234}}, {{0x0100, 0}}};
  HandlerOptions options;
  std::array<std::uint8_t, max_pdu_size> out{};
  Served serve(Link link, Recipient recipient, const Bytes& pdu) {
    return serve_request(link, recipient, pdu, out, registers, options);
  }
};

TEST_F(SlaveSessionServing, ThisSlavesRequestIsAnsweredAndAnExceptionIsAFault) {
  for (const auto link : {Link::tcp, Link::rtu}) {
    auto served = serve(link, Recipient::this_slave, {0x04, 0x00, 0x11, 0x00, 0x01});
    EXPECT_EQ(served.length, 4u);
    EXPECT_EQ(served.state, TransactionState::done);
    EXPECT_FALSE(served.fault);
    served = serve(link, Recipient::this_slave, {0x04, 0x00, 0x12, 0x00, 0x01});
    EXPECT_EQ(served.length, 2u);
    EXPECT_EQ(out[1], 0x02);
    EXPECT_EQ(served.state, TransactionState::err02);
    EXPECT_TRUE(served.fault);
  }
}

TEST_F(SlaveSessionServing, AnotherSlavesRequestIsGatewayTargetFailedOnTcpAndSilenceOnRtu) {
  auto served = serve(Link::tcp, Recipient::another_slave, {0x04, 0x00, 0x11, 0x00, 0x01});
  EXPECT_EQ(served.length, 2u);
  EXPECT_EQ(out[0], 0x84);
  EXPECT_EQ(out[1], 0x0B);
  EXPECT_EQ(served.state, TransactionState::not_for_me);
  EXPECT_TRUE(served.fault);
  served = serve(Link::rtu, Recipient::another_slave, {0x06, 0x01, 0x00, 0x00, 0x05});
  EXPECT_EQ(served.length, 0u);
  EXPECT_EQ(served.state, TransactionState::not_for_me);
  EXPECT_FALSE(served.fault);
  EXPECT_EQ(registers.writable.at(0x0100), 0);  // not applied
}

// SPEC §14: behind a gateway, a unit id it does not route has no path: 0x0A.
TEST_F(SlaveSessionServing, AnotherSlavesRequestBehindAGatewayIsGatewayPathUnavailable) {
  const Bytes pdu{0x03, 0x00, 0x11, 0x00, 0x01};
  const auto served = serve_request(Link::tcp, Recipient::another_slave, pdu, out, registers, options, nullptr, true);
  EXPECT_EQ(served.length, 2u);
  EXPECT_EQ(out[0], 0x83);
  EXPECT_EQ(out[1], 0x0A);
  EXPECT_EQ(served.state, TransactionState::not_for_me);
  EXPECT_TRUE(served.fault);
}

TEST_F(SlaveSessionServing, ABroadcastWriteAppliesUnansweredAndNeverFaults) {
  auto served = serve(Link::rtu, Recipient::broadcast, {0x06, 0x01, 0x00, 0x00, 0x05});
  EXPECT_EQ(served.length, 0u);
  EXPECT_EQ(served.state, TransactionState::done);
  EXPECT_EQ(registers.writable.at(0x0100), 5);
  served = serve(Link::rtu, Recipient::broadcast, {0x06, 0x02, 0x00, 0x00, 0x05});  // not ours: another slave's
  EXPECT_EQ(served.length, 0u);
  EXPECT_EQ(served.state, TransactionState::err02);
  EXPECT_FALSE(served.fault);
}

// SPEC §10: a write the state file could not keep changed nothing; the master learns it
// from exception 04 (server device failure), the monitor from Err04, the front panel from
// the Error bit. A broadcast is still not answered.
TEST_F(SlaveSessionServing, AWriteTheStateFileRefusedIsExceptionFourAndAFault) {
  for (const std::uint8_t function : {0x06, 0x10}) {
    out.fill(0xEE);
    auto refused = refuse_unkept_write(Recipient::this_slave, function, out);
    EXPECT_EQ(refused.length, 2u);
    EXPECT_EQ(out[0], function | 0x80);
    EXPECT_EQ(out[1], 0x04);
    EXPECT_EQ(refused.state, TransactionState::err04);
    EXPECT_TRUE(refused.fault);
    EXPECT_EQ(refused.kept_as, 0u);
    refused = refuse_unkept_write(Recipient::broadcast, function, out);
    EXPECT_EQ(refused.length, 0u);
    EXPECT_EQ(refused.state, TransactionState::err04);
    EXPECT_FALSE(refused.fault);
  }
}

// One verdict per request (modbus::route): a routed unit's request is forwarded unless the
// client's rights or the gateway's `functions: read` (issue 43, finding 9: the plain port
// forwarded restart and vendor functions from anyone) keep it back.
TEST(SlaveSession, TheGatewayForwardsWhatTheClientAndItsFunctionsAllow) {
  std::array<bool, 256> routed{};
  routed[5] = true;
  using enum Verdict;
  const auto other = Recipient::another_slave;
  EXPECT_EQ(route(Recipient::this_slave, 1, 0x06, &routed, nullptr), serve);
  EXPECT_EQ(route(other, 7, 0x03, &routed, nullptr), serve) << "not routed: answered here (0x0A)";
  EXPECT_EQ(route(other, 5, 0x03, nullptr, nullptr), serve) << "no gateway";
  for (const std::uint8_t function : {0x01, 0x02, 0x03, 0x04, 0x06, 0x08, 0x10, 0x11, 0x2B, 0x41})
    EXPECT_EQ(route(other, 5, function, &routed, nullptr), forward) << int(function);
  for (const std::uint8_t read : {0x01, 0x02, 0x03, 0x04}) EXPECT_EQ(route(other, 5, read, &routed, nullptr, true), forward);
  for (const std::uint8_t function : {0x05, 0x06, 0x08, 0x0F, 0x10, 0x11, 0x17, 0x2B, 0x41})
    EXPECT_EQ(route(other, 5, function, &routed, nullptr, true), refuse_forward) << int(function);
  const auto everything = WriteRights::everything();
  EXPECT_EQ(route(other, 5, 0x08, &routed, &everything, true), refuse_forward) << "no role widens functions: read";
  const auto nothing = WriteRights::nothing();
  EXPECT_EQ(route(other, 5, 0x06, &routed, &nothing), refuse_forward);
  EXPECT_EQ(route(other, 5, 0x04, &routed, &nothing), forward);
}

TEST(RequestHandler, ARefusedWriteIsAnsweredWithTheExceptionItsStatusMeans) {
  std::array<std::uint8_t, max_pdu_size> out{};
  EXPECT_EQ(answer_refused_write(0x06, WriteResult::Status::not_kept, out), 2u);
  EXPECT_EQ(exception_of(std::span(out).first(2)), ExceptionCode::server_device_failure);
  answer_refused_write(0x10, WriteResult::Status::not_allowed, out);
  EXPECT_EQ(out[0], 0x90);
  EXPECT_EQ(exception_of(std::span(out).first(2)), ExceptionCode::illegal_function);
}

}  // namespace
}  // namespace unima::modbus
