// The RTU line in the config: what check and the start-up log warn about now that the
// line is served (issue #4).

#include <gtest/gtest.h>

#include "config/config.hpp"

namespace unima {
namespace {

config::Config load(const std::string& yaml) { return config::load_text(yaml, "t.yaml"); }

TEST(RtuConfig, AServedLineIsNoWarning) {
  const auto c = load("modbus:\n  rtu: { device: /dev/ttyUSB0, baud: 14400, parity: even, stop_bits: 2 }\n"
                      "blocks:\n  - { type: capture, device: 3, register: 0x0202, output: 2 }\n");
  ASSERT_TRUE(c.modbus.rtu);
  EXPECT_EQ(c.modbus.rtu->baud, 14400u);
  EXPECT_TRUE(config::warnings(c).empty());
}

TEST(RtuConfig, ACaptureBlockWithoutALineIsInactiveWithAWarning) {
  const auto c = load("blocks:\n  - { type: capture, device: 3, register: 0x0202, output: 2 }\n");
  const auto w = config::warnings(c);
  ASSERT_EQ(w.size(), 1u);
  EXPECT_EQ(w[0], "t.yaml:2:5: capture block inactive: capture listens on a Modbus RTU line, and modbus.rtu is not set");
}

}  // namespace
}  // namespace unima
