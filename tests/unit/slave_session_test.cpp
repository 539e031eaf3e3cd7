// modbus::serve_request and recipient_of: whose request it is on TCP and on RTU, what is
// answered, the state the monitor logs and what counts as a fault — the same for both ports.

#include <gtest/gtest.h>

#include <array>
#include <vector>

#include "modbus/slave_session.hpp"
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

}  // namespace
}  // namespace unima::modbus
