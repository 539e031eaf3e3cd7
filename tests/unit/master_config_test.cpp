// Master mode in the config (SPEC §4, §7; docs/master.md): the modbus.master section, the
// poll and send keys beyond the seed (function, data_type, count, word_order, scale,
// profile, point), and every error with file:line:column.

#include <gtest/gtest.h>

#include "config/config.hpp"
#include "config/master_setup.hpp"
#include "tests/support/error_message.hpp"

namespace unima::config {
namespace {

using namespace std::chrono_literals;
using master::ValueType;
using master::WordOrder;

const std::string rtu_master =
    "modbus:\n"
    "  mode: master\n"
    "  rtu: { device: /dev/ttyUSB0, baud: 38400 }\n";

// The parse alone: these machines have no serial line (check_on_host would warn of it).
Config load(const std::string& yaml) { return parse_text(yaml, "m.yaml", Host{}); }

std::string error(const std::string& yaml) {
  return test_support::error_message<ConfigError>([&] { (void)load(yaml); });
}

TEST(MasterConfig, ModeMasterWithTheMasterSection) {
  const auto c = load(
      "modbus:\n"
      "  mode: master\n"
      "  rtu: { device: /dev/ttyUSB0, baud: 38400 }\n"
      "  master:\n"
      "    response_timeout: 200ms\n"
      "    retries: 2\n"
      "    merge_gap: 4\n"
      "    max_read_registers: 60\n"
      "    stale_after: 3s\n"
      "    degrade_after: 5\n"
      "    backoff: 2s\n"
      "    backoff_max: 20s\n"
      "    min_gap: 5ms\n"
      "    devices:\n"
      "      1: { profile: sic184-v3 }\n"
      "      3: { profile: stepper-driver, min_gap: 50ms, response_timeout: 300ms, line: { baud: 38400 } }\n");
  EXPECT_EQ(c.modbus.mode, ModbusMode::master);
  const auto& m = c.modbus.master;
  EXPECT_EQ(m.response_timeout, 200ms);
  EXPECT_EQ(m.retries, 2u);
  EXPECT_EQ(m.merge_gap, 4u);
  EXPECT_EQ(m.max_read_registers, 60u);
  EXPECT_EQ(m.stale_after, 3s);
  EXPECT_EQ(m.degrade_after, 5u);
  EXPECT_EQ(m.backoff, 2s);
  EXPECT_EQ(m.backoff_max, 20s);
  EXPECT_EQ(m.min_gap, 5ms);
  ASSERT_EQ(m.devices.size(), 2u);
  EXPECT_EQ(m.devices.at(1).profile, master::find_profile("sic184-v3"));
  EXPECT_EQ(m.devices.at(3).min_gap, 50ms);
  EXPECT_EQ(m.devices.at(3).response_timeout, 300ms);
  EXPECT_TRUE(warnings(c).empty());  // the RTU line is the master's: no "TCP only" warning
}

// Seeds 000–002 give each device's serial defaults and the time it takes to answer
// (SPEC §9): check warns where the config contradicts them.
TEST(MasterConfig, ALineOtherThanAPolledDevicesIsAWarningNamingBoth) {
  const auto c = load(
      "modbus:\n"
      "  mode: master\n"
      "  rtu: { device: /dev/ttyUSB0, baud: 19200, parity: even }\n"
      "blocks:\n"
      "  - { type: poll, device: 3, profile: stepper-driver, point: STEP_ANGLE, period: 1s, output: 1 }\n"
      "  - { type: poll, device: 4, profile: sic184-v2, point: OUT, period: 1s, output: 2 }\n");
  const auto w = warnings(c);
  ASSERT_EQ(w.size(), 2u) << (w.empty() ? "" : w[0]);
  EXPECT_EQ(w[0], "m.yaml:3:8: warning: modbus.rtu is 19200 baud 8E1, but device 3 (stepper-driver at m.yaml:5:5) talks at "
                  "9600 baud 8N1 by default (seed 002); if it was set to the line's, say so in "
                  "modbus.master.devices.3.line");
  EXPECT_NE(w[1].find("device 4 (sic184-v2 at m.yaml:6:5) talks at 38400 baud 8N2"), std::string::npos) << w[1];
}

TEST(MasterConfig, ADeviceSetToTheLinesSettingsIsNoWarning) {
  const auto c = load(
      "modbus:\n"
      "  mode: master\n"
      "  rtu: { device: /dev/ttyUSB0, baud: 19200 }\n"
      "  master:\n"
      "    devices:\n"
      "      3: { profile: stepper-driver, line: { baud: 19200 } }\n"
      "      4: { profile: stepper-driver, line: { baud: 19200, parity: odd } }\n"
      "blocks:\n"
      "  - { type: poll, device: 3, point: STEP_ANGLE, period: 1s, output: 1 }\n"
      "  - { type: poll, device: 4, point: STEP_ANGLE, period: 1s, output: 2 }\n");
  const auto w = warnings(c);
  ASSERT_EQ(w.size(), 1u);
  EXPECT_EQ(w[0], "m.yaml:3:8: warning: modbus.rtu is 19200 baud 8N1, but device 4 (stepper-driver at m.yaml:7:10) is set to "
                  "19200 baud 8O1");
}

TEST(MasterConfig, AResponseTimeOutBelowTheDevicesReplyTimeIsAWarning) {
  const auto c = load(
      "modbus:\n"
      "  mode: master\n"
      "  rtu: { device: /dev/ttyUSB0, baud: 9600 }\n"
      "  master:\n"
      "    response_timeout: 30ms\n"
      "    devices:\n"
      "      5: { profile: stepper-driver, response_timeout: 20ms }\n"
      "blocks:\n"
      "  - { type: poll, device: 3, profile: stepper-driver, point: STEP_ANGLE, period: 1s, output: 1 }\n"
      "  - { type: poll, device: 5, point: STEP_ANGLE, period: 1s, output: 2 }\n");
  const auto w = warnings(c);
  ASSERT_EQ(w.size(), 2u);
  EXPECT_EQ(w[0], "m.yaml:5:5: warning: device 3 is a stepper-driver, which takes at least 35 ms to answer (seed 002), but its "
                  "response time-out is 30 ms: every request would time out");
  EXPECT_NE(w[1].find("m.yaml:7:10: warning: device 5"), std::string::npos) << w[1];
  // Over TCP there is no serial line to compare, but the device is as slow.
  const auto tcp = load(
      "modbus:\n"
      "  mode: master\n"
      "  master: { tcp: 127.0.0.1:1502, response_timeout: 30ms }\n"
      "blocks:\n"
      "  - { type: poll, device: 3, profile: stepper-driver, point: STEP_ANGLE, period: 1s, output: 1 }\n");
  ASSERT_EQ(warnings(tcp).size(), 1u);
  EXPECT_NE(warnings(tcp)[0].find("35 ms"), std::string::npos);
}

// Seed 003: a poll or send block names a PLC operand as the PLC's manual does.
TEST(MasterConfig, PlcOperandsBecomeFunctionAddressAndType) {
  const auto c = load(rtu_master +
                      "blocks:\n"
                      "  - { type: poll, device: 3, profile: wecon-lx5v, operand: D200, period: 1s, output: 1 }\n"
                      "  - { type: poll, device: 3, operand: X17, period: 1s, output: 2 }\n"
                      "  - { type: poll, device: 3, operand: D210, data_type: dint, period: 1s, output: 3 }\n"
                      "  - { type: send, device: 3, operand: Y10, period: 1s, source: X.0 }\n"
                      "  - { type: send, device: 3, operand: D220, data_type: dint, period: 1s, source: W+0x00 }\n"
                      "  - { type: send, device: 3, operand: M100, period: 1s, source: X.1 }\n");
  ASSERT_EQ(c.blocks.size(), 6u);
  const auto& d200 = c.blocks[0];
  EXPECT_EQ(d200.function, 3);
  EXPECT_EQ(d200.reg, 200);
  EXPECT_EQ(d200.data_type, master::ValueType::word);
  EXPECT_EQ(d200.point, "D200");
  const auto& x17 = c.blocks[1];
  EXPECT_EQ(x17.function, 2);
  EXPECT_EQ(x17.reg, 0xF80F);
  EXPECT_EQ(x17.data_type, master::ValueType::bits);
  const auto& pair = c.blocks[2];
  EXPECT_EQ(pair.function, 3);
  EXPECT_EQ(pair.extent(), 2);
  EXPECT_EQ(pair.word_order, master::WordOrder::low_first);  // D(n) low, D(n+1) high
  EXPECT_EQ(c.blocks[3].function, 5);
  EXPECT_EQ(c.blocks[3].reg, 0xFC08);
  EXPECT_EQ(c.blocks[4].function, 16);  // a 32-bit value takes two registers
  EXPECT_EQ(c.blocks[5].reg, 100);
}

TEST(MasterConfig, AWrongOperandIsAnErrorAtItsPlace) {
  EXPECT_EQ(error(rtu_master + "blocks:\n  - { type: poll, device: 3, profile: wecon-lx5v, operand: X18, period: 1s, output: 1 }\n"),
            "m.yaml:5:60: 'X18': X operands are numbered in octal (X0..X7, X10..), so '18' has no 8 or 9");
  EXPECT_EQ(error(rtu_master + "blocks:\n  - { type: send, device: 3, profile: wecon-lx5v, operand: X0, period: 1s, source: X.0 }\n"),
            "m.yaml:5:60: X0 cannot be written: the PLC's X are read only (Input relay)");
  EXPECT_EQ(error(rtu_master + "blocks:\n  - { type: poll, device: 3, profile: sic184-v3, operand: D1, period: 1s, output: 1 }\n"),
            "m.yaml:5:59: an operand needs the profile of a PLC named by operands (e.g. 'profile: wecon-lx5v'); "
            "sic184-v3 has points");
  EXPECT_EQ(error(rtu_master + "blocks:\n  - { type: poll, device: 3, profile: wecon-lx5v, operand: D1, function: 4, period: 1s, output: 1 }\n"),
            "m.yaml:5:74: D1 is read with function 3, not 4");
}

TEST(MasterConfig, TheMasterNeedsOneLine) {
  EXPECT_EQ(error("modbus:\n  mode: master\n"),
            "m.yaml:2:9: master mode needs the line to drive: modbus.rtu, or modbus.master.tcp (host:port)");
  EXPECT_EQ(error(rtu_master + "  master: { tcp: 127.0.0.1:1502 }\n"),
            "m.yaml:4:18: modbus.master.tcp and modbus.rtu are both set; the master drives one line: remove one of them");
  const auto tcp = load("modbus:\n  mode: master\n  master: { tcp: 127.0.0.1:1502 }\n");
  EXPECT_EQ(tcp.modbus.master.tcp, "127.0.0.1:1502");
  EXPECT_EQ(error("modbus:\n  mode: master\n  master: { tcp: localhost }\n"), "m.yaml:3:18: 'localhost' is not host:port");
  EXPECT_EQ(error(rtu_master + "  master: { timeout: 1s }\n"),
            "m.yaml:4:13: unknown key 'timeout' in modbus.master (known: tcp, response_timeout, retries, merge_gap, "
            "max_read_registers, stale_after, degrade_after, backoff, backoff_max, min_gap, devices)");
  EXPECT_EQ(error(rtu_master + "  master: { devices: { 1: { profile: sic185 } } }\n"),
            "m.yaml:4:38: unknown device profile 'sic185' (known: sic184-v2, sic184-v3, stepper-driver, wecon-lx5v)");
  EXPECT_EQ(error(rtu_master + "  master: { devices: { 300: {} } }\n"), "m.yaml:4:24: 300 is out of range 1..247");
}

TEST(MasterConfig, SeedBlocksKeepTheSeedsFunctions) {
  const auto c = load(rtu_master +
                      "blocks:\n"
                      "  - { type: poll, device: 1, register: 0x0200, period: 1s, output: 3 }\n"
                      "  - { type: send, device: 1, register: 0x0201, period: 2s, source: W+0x00 }\n");
  ASSERT_EQ(c.active_blocks().size(), 2u);
  EXPECT_EQ(c.blocks[0].function, 4);
  EXPECT_EQ(c.blocks[0].data_type, ValueType::word);
  EXPECT_EQ(c.blocks[0].scale, 1.0);
  EXPECT_EQ(c.blocks[1].function, 6);
}

TEST(MasterConfig, ProfilePoints) {
  const auto c = load(rtu_master +
                      "blocks:\n"
                      "  - { type: poll, device: 1, profile: sic184-v3, point: POS_ACT_REAL, period: 200ms, output: 1 }\n"
                      "  - { type: poll, device: 1, point: IN, period: 200ms, output: 2 }\n"
                      "  - { type: send, device: 1, point: OUT2, period: 1s, source: X.0 }\n"
                      "  - { type: send, device: 1, point: VEL_ABS_INT, period: 1s, source: W+0x01, scale: 0.1 }\n"
                      "  - { type: poll, device: 1, point: POWER, function: 3, period: 1s, output: 3 }\n");
  const auto& b = c.blocks;
  EXPECT_EQ(b[0].reg, 1060);
  EXPECT_EQ(b[0].function, 3);
  EXPECT_EQ(b[0].data_type, ValueType::real);
  EXPECT_EQ(b[0].scale, 10);  // the profile's scale into 0.1 units
  EXPECT_EQ(b[0].point, "POS_ACT_REAL");
  EXPECT_EQ(b[0].extent(), 2);
  EXPECT_EQ(b[1].profile, master::find_profile("sic184-v3"));  // the device's, from the first block
  EXPECT_EQ(b[1].function, 2);
  EXPECT_EQ(b[1].count, 8);
  EXPECT_EQ(b[2].function, 5);
  EXPECT_EQ(b[2].reg, 6001);
  EXPECT_EQ(b[3].function, 16);
  EXPECT_EQ(b[3].data_type, ValueType::dint);
  EXPECT_EQ(b[3].scale, 0.1);
}

TEST(MasterConfig, PointErrors) {
  const auto block = [](const std::string& b) { return rtu_master + "blocks:\n  - " + b + "\n"; };
  EXPECT_EQ(error(block("{ type: poll, device: 1, point: POS_ACT_INT, period: 1s, output: 1 }")),
            "m.yaml:5:37: a point needs a device profile: set 'profile' here, or modbus.master.devices.1.profile");
  EXPECT_EQ(error(block("{ type: poll, device: 1, profile: sic184-v3, point: POS_ACT, period: 1s, output: 1 }")),
            "m.yaml:5:57: profile sic184-v3 has no point 'POS_ACT' (`unima-bridge profiles sic184-v3` lists them)");
  EXPECT_EQ(error(block("{ type: poll, device: 1, profile: sic184-v3, point: HOME_INT, period: 1s, output: 1 }")),
            "m.yaml:5:57: HOME_INT cannot be read (the device writes it only)");
  EXPECT_EQ(error(block("{ type: send, device: 1, profile: sic184-v3, point: STATUS, period: 1s, source: W+0x00 }")),
            "m.yaml:5:57: STATUS cannot be written (the device reads it only)");
  EXPECT_EQ(error(block("{ type: poll, device: 1, profile: sic184-v3, point: POS_ACT_INT, register: 3, period: 1s, "
                        "output: 1 }")),
            "m.yaml:5:80: 'register' comes from the profile's point; leave it out");
  EXPECT_EQ(error(block("{ type: poll, device: 1, profile: sic184-v3, point: STATUS, function: 4, period: 1s, output: 1 }")),
            "m.yaml:5:75: STATUS is read with function 3, not 4");
  EXPECT_EQ(error(block("{ type: poll, device: 1, profile: sic184-v3, point: USER_REGISTER, period: 1s, output: 1 }")),
            "m.yaml:5:57: USER_REGISTER is an area of 500 registers from 0; name one of them with 'register' (and "
            "'data_type') instead of 'point'");
  EXPECT_EQ(error(rtu_master + "blocks:\n"
                  "  - { type: poll, device: 1, profile: sic184-v3, point: STATUS, period: 1s, output: 1 }\n"
                  "  - { type: poll, device: 1, profile: sic184-v2, point: XACT, period: 1s, output: 2 }\n"),
            "m.yaml:6:39: device 1 is a sic184-v3 in the block at m.yaml:5:5");
}

TEST(MasterConfig, RegisterBlocksBeyondTheSeed) {
  const auto c = load(rtu_master +
                      "blocks:\n"
                      "  - { type: poll, device: 2, register: 10, function: 3, data_type: dint, word_order: high_first, "
                      "scale: 0.5, period: 1s, output: 1 }\n"
                      "  - { type: poll, device: 2, register: 5000, function: 2, count: 6, period: 1s, output: 2 }\n"
                      "  - { type: send, device: 2, register: 9, function: 16, data_type: dword, period: 1s, source: W+0x00 }\n"
                      "  - { type: send, device: 2, register: 7, function: 5, period: 1s, source: X.1 }\n"
                      "  - { type: poll, device: 3, profile: sic184-v2, register: 52, function: 3, data_type: real, "
                      "period: 1s, output: 3 }\n");
  const auto& b = c.blocks;
  EXPECT_EQ(b[0].data_type, ValueType::dint);
  EXPECT_EQ(b[0].word_order, WordOrder::high_first);
  EXPECT_EQ(b[0].scale, 0.5);
  EXPECT_EQ(b[1].data_type, ValueType::bits);
  EXPECT_EQ(b[1].count, 6);
  EXPECT_EQ(b[2].function, 16);
  EXPECT_EQ(b[2].extent(), 2);
  EXPECT_EQ(b[3].data_type, ValueType::bits);
  EXPECT_EQ(b[4].word_order, WordOrder::low_first);
}

TEST(MasterConfig, RegisterBlockErrors) {
  const auto block = [](const std::string& b) { return rtu_master + "blocks:\n  - " + b + "\n"; };
  EXPECT_EQ(error(block("{ type: poll, device: 1, profile: sic184-v3, register: 1002, period: 1s, output: 1 }")),
            "m.yaml:5:5: sic184-v3 does not implement function 4 (it implements 1, 2, 3, 5, 6, 16); set 'function'");
  EXPECT_EQ(error(block("{ type: poll, device: 1, register: 1, function: 6, period: 1s, output: 1 }")),
            "m.yaml:5:53: '6' is not one of: 1, 2, 3, 4");
  EXPECT_EQ(error(block("{ type: send, device: 1, register: 1, data_type: real, period: 1s, source: W+0x00 }")),
            "m.yaml:5:54: function 6 does not write real (function 6 writes one register: word or int)");
  EXPECT_EQ(error(block("{ type: poll, device: 1, register: 1, function: 1, data_type: word, period: 1s, output: 1 }")),
            "m.yaml:5:67: function 1 does not read word");
  EXPECT_EQ(error(block("{ type: poll, device: 1, register: 1, count: 4, period: 1s, output: 1 }")),
            "m.yaml:5:50: 'count' is for bits (functions 1 and 2): how many are read into the output");
  EXPECT_EQ(error(block("{ type: poll, device: 1, register: 1, word_order: high_first, period: 1s, output: 1 }")),
            "m.yaml:5:55: word_order is for the 32-bit types (dint, dword, real)");
  EXPECT_EQ(error(block("{ type: poll, device: 1, register: 1, scale: zero, period: 1s, output: 1 }")),
            "m.yaml:5:50: 'zero' is not a number");
  EXPECT_EQ(error(block("{ type: poll, device: 1, register: 1, scale: 0, period: 1s, output: 1 }")),
            "m.yaml:5:50: scale must be a number other than 0");
  EXPECT_EQ(error(block("{ type: poll, device: 1, register: 1, data_type: float, function: 3, period: 1s, output: 1 }")),
            "m.yaml:5:54: 'float' is not one of: bits, word, int, dint, dword, real");
  EXPECT_EQ(error(block("{ type: poll, device: 1, register: 0xFFFF, function: 3, data_type: dint, period: 1s, output: 1 }")),
            "m.yaml:5:40: the value runs past register 0xFFFF");
}

TEST(MasterConfig, Warnings) {
  const auto slave = load("modbus:\n  master: { retries: 2 }\n");
  ASSERT_EQ(warnings(slave).size(), 1u);
  EXPECT_EQ(warnings(slave)[0], "m.yaml:2:11: warning: modbus.master is set, but this bridge is a slave; the master settings are unused");
  const auto master = load(rtu_master + "blocks:\n  - { type: write, register: 0x0201, output: 1 }\n");
  ASSERT_EQ(warnings(master).size(), 1u);
  EXPECT_EQ(warnings(master)[0], "m.yaml:5:5: warning: write block ignored: write blocks act in slave mode only, this bridge is a master");
}

TEST(MasterSetup, BlocksTimingAndLine) {
  const auto c = load(
      "modbus:\n"
      "  mode: master\n"
      "  rtu: { device: /dev/ttyUSB0, baud: 9600, parity: even }\n"
      "  master:\n"
      "    response_timeout: 300ms\n"
      "    stale_after: 5s\n"
      "    merge_gap: 3\n"
      "    devices: { 2: { min_gap: 20ms } }\n"
      "blocks:\n"
      "  - { type: poll, device: 1, profile: stepper-driver, point: STEP_ANGLE, period: 1s, output: 1 }\n"
      "  - { type: send, device: 1, point: SUBDIVISION, period: 1s, source: W+0x00 }\n"
      "  - { type: poll, device: 2, profile: sic184-v2, point: XACT, period: 10s, output: 2 }\n"
      "  - { type: write, register: 0x0201, output: 3 }\n");
  const auto setup = master_setup(c);
  ASSERT_EQ(setup.blocks.size(), 3u);
  EXPECT_EQ(setup.blocks[0].name, "STEP_ANGLE");
  EXPECT_EQ(setup.blocks[0].scale, 0.1);
  EXPECT_EQ(setup.blocks[1].kind, master::MasterBlock::Kind::send);
  ASSERT_TRUE(setup.sources[1]);
  EXPECT_EQ(setup.sources[1]->text, "W+0x00");
  EXPECT_EQ(setup.stale_after[0], 5s);
  EXPECT_EQ(setup.stale_after[2], 20s);  // never shorter than two periods
  EXPECT_EQ(setup.plan.merge_gap, 3u);
  ASSERT_TRUE(setup.serial);
  EXPECT_EQ(setup.serial->bits_per_character, 11u);
  // t3.5 at 9600 baud, 11 bits, is 4011 µs; the SIC184 v2.08 wants at least 1.75 ms.
  EXPECT_EQ(setup.scheduler.frame_gap, std::chrono::microseconds(4011));
  EXPECT_EQ(setup.devices.at(1).min_gap, 35ms);  // the stepper driver's profile
  EXPECT_EQ(setup.devices.at(1).response_timeout, 300ms);
  EXPECT_EQ(setup.devices.at(2).min_gap, 20ms);  // the device's own setting beats its profile
}

}  // namespace
}  // namespace unima::config
