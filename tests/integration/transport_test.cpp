// The UnimaBUS transports other than the feed (SPEC §6), in the real daemon: the
// simulator, and a recording made by `record` played back by `replay`.

#include "tests/integration/bridge_fixture.hpp"

namespace unima::test {
namespace {

class Transport : public BridgeTest {};

TEST_F(Transport, TheSimulatorFillsEachComponentOfAUnit) {
  config.transport = "sim";
  config.unimabus_extra = "  sim: { period: 50ms }\n";
  config.banks = "{ D1: 0x0011, D2: 0x0111, D3: 0x0211, W: 0x0100 }";
  config.devices =
      "{ D1: { type: unigen-chp, address: 5 }, D2: { type: usc, address: 5 }, D3: { type: uvr, address: 5 } }";
  start();
  ModbusClient client(config.modbus_port);
  ASSERT_TRUE(eventually([&] { return client.read_input(0x1033, 1) == std::vector<std::uint16_t>{0x0007}; }))
      << daemon->log();
  // Each bank has its own values: the tables differ, so would their sims.
  const auto d1 = client.read_input(0x0011, 8);
  const auto d2 = client.read_input(0x0111, 8);
  const auto d3 = client.read_input(0x0211, 8);
  ASSERT_TRUE(d1 && d2 && d3);
  EXPECT_NE(*d1, *d2);
  EXPECT_NE(*d2, *d3);
}

}  // namespace
}  // namespace unima::test
