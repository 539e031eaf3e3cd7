#include "tests/integration/rtu_fixture.hpp"

namespace unima::test {

void RtuTest::SetUp() {
  BridgeTest::SetUp();
  line = std::make_unique<PtyLine>(dir.path() / "ttyRTU");
}

std::string RtuTest::rtu_yaml(const std::string& device) const {
  return "  rtu: { device: " + (device.empty() ? line->link().string() : device) + ", baud: " + std::to_string(baud) +
         " }\n";
}

void RtuTest::start_rtu(const std::string& more, const std::string& device) {
  config.modbus_extra = rtu_yaml(device);
  daemon = std::make_unique<Daemon>(dir, config.yaml() + more);
  ASSERT_TRUE(wait_for_port(config.modbus_port)) << daemon->log();
  ASSERT_TRUE(wait_for_port(config.feed_port)) << daemon->log();
  ASSERT_TRUE(daemon->wait_for_log("modbus rtu: serving unit 1")) << daemon->log();
}

Bytes RtuTest::exchange(const Bytes& query, std::size_t size) {
  line->write(query);
  return line->read(size);
}

void RtuTest::expect_next_reply_is_to_a_read_of_w(std::uint16_t value) {
  const auto reply = exchange(rtu_adu(1, {0x04, 0x01, 0x00, 0x00, 0x01}), 7);
  EXPECT_EQ(reply, rtu_adu(1, {0x04, 0x02, static_cast<std::uint8_t>(value >> 8), static_cast<std::uint8_t>(value)}));
}

bool RtuTest::error_bit_set() {
  ModbusClient tcp(config.modbus_port);
  const auto online = tcp.read_input(0x1033, 1);  // C+0x13 at the default base
  return online && ((*online)[0] & 0x8000) != 0;
}

}  // namespace unima::test
