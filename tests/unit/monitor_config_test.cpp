// The monitor: and status: sections of the config (SPEC §7): values, defaults, and errors
// that name file:line:column.

#include <gtest/gtest.h>

#include "config/config.hpp"
#include "tests/support/error_message.hpp"

namespace unima::config {
namespace {

std::string error_of(const std::string& yaml) {
  return test_support::error_message<ConfigError>([&] { (void)load_text(yaml, "bridge.yaml"); }, "accepted");
}

TEST(MonitorConfig, TheSpecExample) {
  const auto c = load_text(
      "monitor:\n"
      "  file: /var/log/unima-bridge/monitor.log\n"
      "  filter: { address: xx, function: xx, from: 0x0000, to: 0xFFFF }\n"
      "  indicators: [ { address: 3, register: 0x0202 } ]\n",
      "bridge.yaml");
  EXPECT_EQ(c.monitor.file, "/var/log/unima-bridge/monitor.log");
  EXPECT_TRUE(c.monitor.enabled());
  EXPECT_FALSE(c.monitor.filter.address);
  EXPECT_FALSE(c.monitor.filter.function);
  EXPECT_EQ(c.monitor.filter.from, 0x0000);
  EXPECT_EQ(c.monitor.filter.to, 0xFFFF);
  ASSERT_EQ(c.monitor.indicators.size(), 1u);
  EXPECT_EQ(c.monitor.indicators[0].address, 3);
  EXPECT_EQ(c.monitor.indicators[0].reg, 0x0202);
}

TEST(MonitorConfig, Defaults) {
  const auto c = load_text("", "bridge.yaml");
  EXPECT_FALSE(c.monitor.enabled());
  EXPECT_EQ(c.monitor.max_size, 10u << 20);
  EXPECT_EQ(c.monitor.max_files, 5u);
  EXPECT_EQ(c.monitor.format, monitor::MonitorFormat::text);
  EXPECT_EQ(c.status.socket, "/run/unima-bridge/control.sock");
}

TEST(MonitorConfig, EveryKey) {
  const auto c = load_text(
      "monitor:\n"
      "  stdout: true\n"
      "  format: json\n"
      "  max_size: 64k\n"
      "  max_files: 2\n"
      "  queue: 100\n"
      "  filter: { address: 3, function: 6, from: 0x0200, to: 0x0210 }\n"
      "status: { socket: /tmp/x.sock }\n",
      "bridge.yaml");
  EXPECT_TRUE(c.monitor.to_stdout);
  EXPECT_TRUE(c.monitor.enabled());
  EXPECT_EQ(c.monitor.format, monitor::MonitorFormat::json);
  EXPECT_EQ(c.monitor.max_size, 65536u);
  EXPECT_EQ(c.monitor.max_files, 2u);
  EXPECT_EQ(c.monitor.queue, 100u);
  EXPECT_EQ(c.monitor.filter.address, 3);
  EXPECT_EQ(c.monitor.filter.function, 6);
  EXPECT_EQ(c.monitor.filter.from, 0x0200);
  EXPECT_EQ(c.monitor.filter.to, 0x0210);
  EXPECT_EQ(c.status.socket, "/tmp/x.sock");
  EXPECT_EQ(load_text("monitor: { max_size: 10MB }", "b").monitor.max_size, 10u << 20);
  EXPECT_EQ(load_text("monitor: { max_size: 5000 }", "b").monitor.max_size, 5000u);
}

TEST(MonitorConfig, ErrorsNameTheirPosition) {
  EXPECT_EQ(error_of("monitor:\n  flie: x\n"),
            "bridge.yaml:2:3: unknown key 'flie' in monitor (known: file, stdout, format, max_size, max_files, queue, "
            "filter, indicators)");
  EXPECT_EQ(error_of("monitor:\n  filter: { address: yy }\n"),
            "bridge.yaml:2:22: monitor.filter: 'yy' is not xx or a number 0..255");
  EXPECT_EQ(error_of("monitor:\n  filter: { register: 5 }\n"),
            "bridge.yaml:2:13: unknown key 'register' in monitor.filter (known: address, function, from, to)");
  EXPECT_EQ(error_of("monitor:\n  filter: { from: 0x0300, to: 0x0200 }\n"),
            "bridge.yaml:2:31: monitor.filter: from=0x0300 is after to=0x0200");
  EXPECT_EQ(error_of("monitor:\n  indicators:\n    - { address: 1, register: 1 }\n    - { address: 1, register: 2 }\n"
                     "    - { address: 1, register: 3 }\n    - { address: 1, register: 4 }\n"
                     "    - { address: 1, register: 5 }\n"),
            "bridge.yaml:7:7: at most 4 capture indicators (seed 004 §8)");
  EXPECT_EQ(error_of("monitor:\n  indicators: [ { address: 1 } ]\n"),
            "bridge.yaml:2:17: an indicator needs an address and a register");
  EXPECT_EQ(error_of("monitor:\n  max_size: 10 parsecs\n"), "bridge.yaml:2:13: '10 parsecs' is not a size (write e.g. 65536, 64k, 10MB)");
  EXPECT_EQ(error_of("monitor:\n  max_size: 1k\n"), "bridge.yaml:2:13: 1k is out of range 4096..1099511627776 bytes");
  EXPECT_EQ(error_of("monitor:\n  format: xml\n"), "bridge.yaml:2:11: 'xml' is not one of: text, json");
  EXPECT_EQ(error_of("status:\n  sock: /x\n"), "bridge.yaml:2:3: unknown key 'sock' in status (known: socket)");
  EXPECT_EQ(error_of("status:\n  socket: /" + std::string(120, 'a') + "\n"),
            "bridge.yaml:2:11: status.socket must be a path of 1..107 characters (a unix socket's limit)");
}

}  // namespace
}  // namespace unima::config
