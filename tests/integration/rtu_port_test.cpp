// The RTU slave port in-process on a pseudo-terminal: what it reports to the monitor
// (modbus::Transaction: port, state, query and response as on the wire), to the fault
// hold (C+0x13 bit 15) and to capture blocks (the foreign listener).

#include <gtest/gtest.h>

#include <map>

#include "io/modbus/rtu_slave_port.hpp"
#include "tests/integration/rtu_line.hpp"
#include "tests/support/map_registers.hpp"
#include "tests/support/seed_frames.hpp"

namespace unima::test {
namespace {

using modbus::TransactionState;

struct Seen {
  modbus::PortKind port;
  TransactionState state;
  Bytes query;
  Bytes response;
};

class RtuPort : public ::testing::Test {
 protected:
  void SetUp() override {
    line = std::make_unique<PtyLine>(dir.path() / "tty");
    io::SlaveContext context;
    context.registers = &registers;
    context.unit_id = 1;
    context.options.max_read_registers = modbus::max_read_registers_rtu;
    context.on_fault = [this] { ++faults; };
    context.on_transaction = [this](const modbus::Transaction& t) {
      seen.push_back({t.port, t.state, Bytes(t.query.begin(), t.query.end()), Bytes(t.response.begin(), t.response.end())});
    };
    config::RtuConfig rtu;
    rtu.device = line->link().string();
    port = std::make_unique<io::RtuSlavePort>(io, rtu, context);
    port->set_foreign_listener([this](std::span<const std::uint8_t> q, std::span<const std::uint8_t> r) {
      foreign.emplace_back(Bytes(q.begin(), q.end()), Bytes(r.begin(), r.end()));
    });
    port->start();
    ASSERT_TRUE(port->is_open());
  }
  // Runs the port's event loop until `condition` holds.
  bool run_until(const std::function<bool()>& condition, std::chrono::milliseconds timeout = 3000ms) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (!condition()) {
      if (std::chrono::steady_clock::now() >= deadline) return false;
      io.restart();
      io.run_for(std::chrono::milliseconds(5));
    }
    return true;
  }

  TempDir dir;
  std::unique_ptr<PtyLine> line;
  asio::io_context io;
  // 0x0011..0x0012 readable (the seed's example), 0x0101 writable.
  test_support::MapRegisters registers{{{0x11, 0x0050}, {0x12, 0x7FFF}}, {{0x101, 0}}};
  std::unique_ptr<io::RtuSlavePort> port;
  std::vector<Seen> seen;
  std::vector<std::pair<Bytes, Bytes>> foreign;
  int faults = 0;
};

const Bytes seed_read = test_support::seed::read_query;
const Bytes seed_read_response = test_support::seed::read_response;

TEST_F(RtuPort, AnAnsweredQueryIsDoneWithBothFramesAsOnTheWire) {
  line->write(seed_read);
  ASSERT_TRUE(run_until([&] { return !seen.empty(); }));
  EXPECT_EQ(seen[0].port, modbus::PortKind::rtu);
  EXPECT_EQ(seen[0].state, TransactionState::done);
  EXPECT_EQ(seen[0].query, seed_read);
  EXPECT_EQ(seen[0].response, seed_read_response);
  Bytes reply;
  ASSERT_TRUE(run_until([&] {
    const auto got = line->read(9 - reply.size(), 0ms);
    reply.insert(reply.end(), got.begin(), got.end());
    return reply.size() == 9;
  }));
  EXPECT_EQ(reply, seed_read_response);
  EXPECT_EQ(faults, 0);
}

TEST_F(RtuPort, AnExceptionIsItsErrStateAndAFault) {
  line->write(rtu_adu(1, {0x04, 0x00, 0x20, 0x00, 0x01}));
  line->write(rtu_adu(1, {0x01, 0x00, 0x00, 0x00, 0x01}));
  ASSERT_TRUE(run_until([&] { return seen.size() == 2; }));
  EXPECT_EQ(seen[0].state, TransactionState::err02);
  EXPECT_EQ(seen[0].response, rtu_adu(1, {0x84, 0x02}));
  EXPECT_EQ(seen[1].state, TransactionState::err01);
  EXPECT_EQ(faults, 2);
}

TEST_F(RtuPort, ABadCrcIsErr03WithoutResponseAndAFault) {
  Bytes broken = seed_read;
  broken[2] ^= 0x01;
  line->write(broken);
  ASSERT_TRUE(run_until([&] { return !seen.empty(); }));
  EXPECT_EQ(seen[0].state, TransactionState::err03);
  EXPECT_EQ(seen[0].query, broken);
  EXPECT_TRUE(seen[0].response.empty());
  EXPECT_EQ(faults, 1);
}

TEST_F(RtuPort, AForeignQueryIsNot4MeWithTheResponseThatFollows) {
  const auto query = rtu_adu(3, {0x04, 0x02, 0x00, 0x00, 0x01});
  const auto response = rtu_adu(3, {0x04, 0x02, 0x01, 0x2C});
  line->write(query);
  ASSERT_TRUE(run_until([&] { return foreign.size() == 1; }));
  EXPECT_TRUE(seen.empty());  // the monitor line waits for the response
  EXPECT_EQ(foreign[0], std::make_pair(query, Bytes{}));
  line->write(response);
  ASSERT_TRUE(run_until([&] { return !seen.empty(); }));
  EXPECT_EQ(seen[0].state, TransactionState::not_for_me);
  EXPECT_EQ(seen[0].query, query);
  EXPECT_EQ(seen[0].response, response);
  ASSERT_EQ(foreign.size(), 2u);
  EXPECT_EQ(foreign[1], std::make_pair(query, response));
  EXPECT_EQ(faults, 0);
}

TEST_F(RtuPort, AForeignQueryWithoutResponseIsNot4MeAloneWhenTheNextQueryComes) {
  const auto query = rtu_adu(3, {0x06, 0x02, 0x02, 0x00, 0x01});
  line->write(query);
  line->write(seed_read);
  ASSERT_TRUE(run_until([&] { return seen.size() == 2; }));
  EXPECT_EQ(seen[0].state, TransactionState::not_for_me);
  EXPECT_EQ(seen[0].query, query);
  EXPECT_TRUE(seen[0].response.empty());
  EXPECT_EQ(seen[1].state, TransactionState::done);
}

TEST_F(RtuPort, AForeignQueryWithoutResponseIsGivenUpAfterATimeOut) {
  line->write(rtu_adu(3, {0x04, 0x02, 0x00, 0x00, 0x01}));
  ASSERT_TRUE(run_until([&] { return !seen.empty(); },
                        io::RtuSlavePort::foreign_response_timeout + std::chrono::milliseconds(3000)));
  EXPECT_EQ(seen[0].state, TransactionState::not_for_me);
  EXPECT_TRUE(seen[0].response.empty());
}

TEST_F(RtuPort, ABroadcastWriteAppliesWithoutResponseOrFault) {
  const auto write = rtu_adu(0, {0x06, 0x01, 0x01, 0x00, 0x07});
  line->write(write);
  line->write(rtu_adu(0, {0x06, 0x07, 0x77, 0x00, 0x07}));  // a register the bridge does not have
  ASSERT_TRUE(run_until([&] { return seen.size() == 2; }));
  EXPECT_EQ(registers.writable[0x101], 7);
  EXPECT_EQ(seen[0].state, TransactionState::done);
  EXPECT_EQ(seen[0].query, write);
  EXPECT_TRUE(seen[0].response.empty());
  EXPECT_EQ(seen[1].state, TransactionState::err02);
  EXPECT_EQ(faults, 0);
  ASSERT_EQ(foreign.size(), 2u);  // capture blocks hear broadcasts too
  EXPECT_EQ(foreign[0].first, write);
}

}  // namespace
}  // namespace unima::test
