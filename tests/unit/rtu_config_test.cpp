// The RTU line in the config: what check and the start-up log warn about now that the
// line is served (issue #4).

#include <gtest/gtest.h>

#include "config/config.hpp"

namespace unima {
namespace {

// The parse alone: these machines have no serial line (check_on_host would warn of it).
config::Config load(const std::string& yaml) { return config::parse_text(yaml, "t.yaml", config::Host{}); }

TEST(RtuConfig, AServedLineIsNoWarning) {
  const auto c = load("modbus:\n  rtu: { device: /dev/ttyUSB0, baud: 14400, parity: even, stop_bits: 2 }\n"
                      "blocks:\n  - { type: capture, device: 3, register: 0x0202, output: 2 }\n");
  ASSERT_EQ(c.modbus.lines.size(), 1u);
  EXPECT_EQ(c.modbus.lines.at(0).serial.baud, 14400u);
  EXPECT_TRUE(config::warnings(c).empty());
}

TEST(RtuConfig, ACaptureBlockWithoutALineIsInactiveWithAWarning) {
  const auto c = load("blocks:\n  - { type: capture, device: 3, register: 0x0202, output: 2 }\n");
  const auto w = config::warnings(c);
  ASSERT_EQ(w.size(), 1u);
  EXPECT_EQ(w[0], "t.yaml:2:5: warning: capture block inactive: capture listens on a Modbus RTU line, and modbus.rtu is not set");
}

std::string load_error(const std::string& yaml) {
  try {
    (void)load(yaml);
  } catch (const config::ConfigError& e) {
    return e.what();
  }
  ADD_FAILURE() << "accepted: " << yaml;
  return {};
}

TEST(RtuConfig, FrameGapIsAutoOrADurationOfAtLeastT35) {
  EXPECT_FALSE(load("modbus:\n  rtu: { device: /dev/ttyS0 }\n").modbus.lines.at(0).serial.frame_gap);
  EXPECT_FALSE(load("modbus:\n  rtu: { device: /dev/ttyS0, frame_gap: auto }\n").modbus.lines.at(0).serial.frame_gap);
  EXPECT_EQ(load("modbus:\n  rtu: { device: /dev/ttyS0, frame_gap: 2ms }\n").modbus.lines.at(0).serial.frame_gap,
            std::chrono::microseconds(2000));
  EXPECT_EQ(load("modbus:\n  rtu: { device: /dev/ttyS0, baud: 115200, frame_gap: 1750us }\n").modbus.lines.at(0).serial.frame_gap,
            std::chrono::microseconds(1750));
  EXPECT_EQ(load_error("modbus:\n  rtu: { device: /dev/ttyS0, baud: 9600, frame_gap: 2ms }\n"),
            "t.yaml:2:53: frame_gap 2000 µs is shorter than t3.5 at 9600 baud (3646 µs)");
  EXPECT_EQ(load_error("modbus:\n  rtu: { device: /dev/ttyS0, frame_gap: soon }\n"),
            "t.yaml:2:41: 'soon' is not a duration (write e.g. 1750us, 2ms)");
}

TEST(RtuConfig, AnRtuSlaveAnswersAnAddressOf1To247) {
  for (const char* address : {"0", "248", "255"}) {
    const auto error = load_error(std::string("modbus:\n  address: ") + address + "\n  rtu: { device: /dev/ttyS0 }\n");
    EXPECT_EQ(error, std::string("t.yaml:2:12: modbus.address ") + address + " cannot be an RTU slave's address (1..247)");
  }
  EXPECT_EQ(load("modbus:\n  address: 247\n  rtu: { device: /dev/ttyS0 }\n").modbus.address, 247);
  // A TCP slave answers unit id 0 and 255 anyway; without a line, any address stays allowed.
  EXPECT_EQ(load("modbus:\n  address: 0\n").modbus.address, 0);
}

}  // namespace
}  // namespace unima
