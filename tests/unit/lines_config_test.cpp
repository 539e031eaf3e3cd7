// modbus.lines in the config (SPEC §18): named RS-485 lines with their roles, modbus.rtu as
// the one line named `rtu`, the line each block goes on, and every error of several lines
// naming its key with file:line:column.

#include <gtest/gtest.h>

#include "config/config.hpp"
#include "config/master_setup.hpp"
#include "tests/support/error_message.hpp"

namespace unima::config {
namespace {

using namespace std::chrono_literals;

Config lines_parse(const std::string& yaml) { return parse_text(yaml, "l.yaml", Host{}); }

std::string lines_error(const std::string& yaml) {
  return test_support::error_message<ConfigError>([&] { (void)lines_parse(yaml); });
}

// The site: the SCADA on one port, the foreign slaves on the other.
const std::string two_port_modbus =
    "modbus:\n"
    "  lines:\n"
    "    scada: { device: /dev/ttyS0, baud: 19200, parity: even, role: slave }\n"
    "    field: { device: /dev/ttyS1, baud: 9600, role: master, gateway: { units: [2-9] } }\n";

TEST(LinesConfig, ModbusRtuInSlaveModeIsOneSlaveLineNamedRtu) {
  const auto c = lines_parse("modbus:\n  address: 7\n  rtu: { device: /dev/ttyUSB0, baud: 9600 }\n"
                             "blocks:\n  - { type: capture, device: 3, register: 0x0202, output: 2 }\n");
  ASSERT_EQ(c.modbus.lines.size(), 1u);
  const auto& line = c.modbus.lines[0];
  EXPECT_EQ(line.name, "rtu");
  EXPECT_EQ(line.key, "modbus.rtu");
  EXPECT_EQ(line.role, LineRole::slave);
  EXPECT_EQ(line.address, 7);
  EXPECT_EQ(line.serial.device, "/dev/ttyUSB0");
  EXPECT_EQ(line.serial.baud, 9600u);
  EXPECT_FALSE(line.gateway);
  EXPECT_EQ(c.modbus.mode, ModbusMode::slave);
  EXPECT_EQ(c.modbus.line_of(LineRole::slave), &line);
  EXPECT_EQ(c.modbus.line_of(LineRole::master), nullptr);
  ASSERT_EQ(c.blocks.size(), 1u);
  EXPECT_EQ(c.blocks[0].line, "rtu");
  ASSERT_FALSE(c.host_paths.empty());
  EXPECT_EQ(c.host_paths[0].key, "modbus.rtu.device") << "the key the warnings of today name";
}

TEST(LinesConfig, ModbusRtuInMasterModeIsOneMasterLineWithModbusGateway) {
  const auto c = lines_parse("modbus:\n  mode: master\n  rtu: { device: /dev/ttyUSB0 }\n  gateway: { units: [3] }\n"
                             "blocks:\n  - { type: poll, device: 3, register: 0x10, period: 1s, output: 1 }\n");
  ASSERT_EQ(c.modbus.lines.size(), 1u);
  const auto& line = c.modbus.lines[0];
  EXPECT_EQ(line.name, "rtu");
  EXPECT_EQ(line.role, LineRole::master);
  ASSERT_TRUE(line.gateway);
  EXPECT_TRUE(line.gateway->routes(3));
  EXPECT_EQ(c.modbus.gateway(), &*line.gateway);
  EXPECT_EQ(c.modbus.mode, ModbusMode::master);
  EXPECT_EQ(c.blocks[0].line, "rtu");
  EXPECT_EQ(master_setup(c).blocks.size(), 1u);
}

TEST(LinesConfig, NoRtuSectionIsNoLine) {
  EXPECT_TRUE(lines_parse("modbus:\n  tcp: { port: 5020 }\n").modbus.lines.empty());
  const auto tcp_master = lines_parse("modbus:\n  mode: master\n  master: { tcp: 127.0.0.1:1502 }\n"
                                      "blocks:\n  - { type: poll, device: 3, register: 0x10, period: 1s, output: 1 }\n");
  EXPECT_TRUE(tcp_master.modbus.lines.empty());
  EXPECT_EQ(tcp_master.modbus.mode, ModbusMode::master);
  EXPECT_EQ(tcp_master.blocks[0].line, "") << "the master drives modbus.master.tcp, no line";
  EXPECT_EQ(master_setup(tcp_master).blocks.size(), 1u);
  const auto capture = lines_parse("blocks:\n  - { type: capture, device: 3, register: 0x0202, output: 2 }\n");
  EXPECT_EQ(capture.blocks[0].line, "");
}

TEST(LinesConfig, ANamedSlaveLineHasItsSerialKeysAndItsOwnAddress) {
  const auto c = lines_parse("modbus:\n  address: 1\n  lines:\n"
                             "    scada: { device: /dev/ttyS0, baud: 19200, parity: even, stop_bits: 2, frame_gap: 3ms, "
                             "role: slave, address: 9 }\n"
                             "blocks:\n  - { type: capture, device: 3, register: 0x0202, output: 2 }\n");
  ASSERT_EQ(c.modbus.lines.size(), 1u);
  const auto& line = c.modbus.lines[0];
  EXPECT_EQ(line.name, "scada");
  EXPECT_EQ(line.key, "modbus.lines.scada");
  EXPECT_EQ(line.role, LineRole::slave);
  EXPECT_EQ(line.address, 9);
  EXPECT_EQ(line.serial.parity, Parity::even);
  EXPECT_EQ(line.serial.stop_bits, 2u);
  EXPECT_EQ(line.serial.frame_gap, std::chrono::microseconds(3000));
  EXPECT_EQ(c.modbus.mode, ModbusMode::slave);
  EXPECT_EQ(c.blocks[0].line, "scada") << "the only slave line";
  EXPECT_EQ(c.active_blocks().size(), 1u);
  EXPECT_EQ(c.host_paths[0].key, "modbus.lines.scada.device");
  EXPECT_EQ(lines_parse("modbus:\n  address: 4\n  lines:\n    scada: { device: /dev/ttyS0, role: slave }\n")
                .modbus.lines[0]
                .address,
            4)
      << "modbus.address by default";
}

TEST(LinesConfig, ANamedMasterLineCarriesItsBlocksAndItsGateway) {
  const auto c = lines_parse("modbus:\n  lines:\n"
                             "    field: { device: /dev/ttyS1, baud: 9600, role: master, gateway: { units: [2-9] } }\n"
                             "blocks:\n  - { type: poll, device: 2, register: 0x10, period: 1s, output: 1 }\n"
                             "  - { type: read, register: 0x0200, source: C+0x00 }\n");
  EXPECT_EQ(c.modbus.mode, ModbusMode::master) << "the master runs";
  ASSERT_TRUE(c.modbus.gateway());
  EXPECT_TRUE(c.modbus.gateway()->routes(2));
  EXPECT_TRUE(c.modbus.gateway()->routes(9));
  EXPECT_FALSE(c.modbus.gateway()->routes(10));
  EXPECT_EQ(c.blocks[0].line, "field");
  EXPECT_EQ(c.blocks[1].line, "") << "a read block is served on the TCP slave, on no line";
  ASSERT_EQ(c.active_blocks().size(), 1u) << "no slave line: slave blocks are ignored, as in master mode";
  const auto setup = master_setup(c);
  EXPECT_EQ(setup.blocks.size(), 1u);
  ASSERT_TRUE(setup.serial);
  EXPECT_EQ(setup.serial->frame_gap, line_timing(c.modbus.lines[0].serial).frame_gap);
}

TEST(LinesConfig, ALineNameIsOneToSixteenOfLowercaseDigitsUnderscoreAndDash) {
  EXPECT_EQ(lines_error("modbus:\n  lines:\n    Scada: { device: /dev/ttyS0, role: slave }\n"),
            "l.yaml:3:5: modbus.lines: 'Scada' is not a line name (1 to 16 of a-z, 0-9, _ and -)");
  EXPECT_EQ(lines_error("modbus:\n  lines:\n    abcdefghijklmnopq: { device: /dev/ttyS0, role: slave }\n"),
            "l.yaml:3:5: modbus.lines: 'abcdefghijklmnopq' is not a line name (1 to 16 of a-z, 0-9, _ and -)");
  EXPECT_EQ(lines_parse("modbus:\n  lines:\n    port_1-abcdefghi: { device: /dev/ttyS0, role: slave }\n")
                .modbus.lines[0]
                .name,
            "port_1-abcdefghi");
}

TEST(LinesConfig, ANameUsedTwiceIsAnError) {
  EXPECT_EQ(lines_error("modbus:\n  lines:\n    scada: { device: /dev/ttyS0, role: slave }\n"
                        "    scada: { device: /dev/ttyS1, role: master }\n"),
            "l.yaml:4:5: 'scada' is written twice in this mapping (first at line 3, column 5); only one would count: "
            "merge the two");
}

TEST(LinesConfig, TwoLinesOnOneDeviceIsAnError) {
  EXPECT_EQ(lines_error("modbus:\n  lines:\n    scada: { device: /dev/ttyS0, baud: 19200, parity: even, role: slave }\n"
                        "    field: { device: /dev/ttyS0, role: master }\n"),
            "l.yaml:4:22: modbus.lines.field.device: /dev/ttyS0 is already the device of the line scada (l.yaml:3:12); a "
            "serial port carries one line");
}

TEST(LinesConfig, AUnitRoutedByTwoLinesIsAnErrorAtItsSecondMention) {
  EXPECT_EQ(lines_error("modbus:\n  lines:\n"
                        "    field: { device: /dev/ttyS1, role: master, gateway: { units: [2-9] } }\n"
                        "    more: { device: /dev/ttyS2, role: master, gateway: { units: [12, 9] } }\n"),
            "l.yaml:4:70: modbus.lines.more.gateway.units: unit 9 is routed by the line field too (l.yaml:3:57); a unit "
            "id reaches one line");
}

TEST(LinesConfig, ABlockWithoutLineWhereTwoLinesHaveItsRoleIsAnError) {
  EXPECT_EQ(lines_error("modbus:\n  lines:\n    scada: { device: /dev/ttyS0, role: slave }\n"
                        "    panel: { device: /dev/ttyS1, role: slave }\n"
                        "blocks:\n  - { type: capture, device: 3, register: 0x0202, output: 2 }\n"),
            "l.yaml:6:5: a capture block needs 'line': 2 lines are slave lines (scada, panel)");
  EXPECT_EQ(lines_error("modbus:\n  lines:\n    field: { device: /dev/ttyS1, role: master }\n"
                        "    more: { device: /dev/ttyS2, role: master }\n"
                        "blocks:\n  - { type: poll, device: 3, register: 0x10, period: 1s, output: 1 }\n"),
            "l.yaml:6:5: a poll block needs 'line': 2 lines are master lines (field, more)");
}

TEST(LinesConfig, ABlockNamingAnUnknownLineOrOneOfTheOtherRoleIsAnError) {
  EXPECT_EQ(lines_error(two_port_modbus +
                        "blocks:\n  - { type: capture, device: 3, register: 0x0202, output: 2, line: scadaa }\n"),
            "l.yaml:6:68: no line is named 'scadaa' (slave lines: scada)");
  EXPECT_EQ(lines_error(two_port_modbus +
                        "blocks:\n  - { type: capture, device: 3, register: 0x0202, output: 2, line: field }\n"),
            "l.yaml:6:68: the line field is a master line; a capture block goes on a slave line");
  EXPECT_EQ(lines_error("modbus:\n  rtu: { device: /dev/ttyS0 }\n"
                        "blocks:\n  - { type: capture, device: 3, register: 0x0202, output: 2, line: scadaa }\n"),
            "l.yaml:4:68: no line is named 'scadaa' (slave lines: rtu)");
}

TEST(LinesConfig, ASlaveLinesAddressRoutedByAGatewayIsAnError) {
  EXPECT_EQ(lines_error("modbus:\n  lines:\n    scada: { device: /dev/ttyS0, role: slave, address: 5 }\n"
                        "    field: { device: /dev/ttyS1, baud: 9600, role: master, gateway: { units: [2-9] } }\n"),
            "l.yaml:4:79: modbus.lines.field.gateway.units: unit 5 is the address of the slave line scada, which the "
            "bridge answers itself: leave it out");
  EXPECT_EQ(lines_error("modbus:\n  lines:\n"
                        "    field: { device: /dev/ttyS1, role: master, gateway: { units: [1-3] } }\n"),
            "l.yaml:3:67: modbus.lines.field.gateway.units: unit 1 is the bridge's own modbus.address, which serves the "
            "banks: leave it out");
}

TEST(LinesConfig, RoleAddressAndGatewayGoWithTheirRole) {
  EXPECT_EQ(lines_error("modbus:\n  lines:\n    scada: { device: /dev/ttyS0 }\n"),
            "l.yaml:3:12: modbus.lines.scada needs its role: slave (a master such as a SCADA polls the bridge on it) or "
            "master (the bridge polls the foreign slaves on it)");
  EXPECT_EQ(lines_error("modbus:\n  lines:\n    field: { device: /dev/ttyS1, role: master, address: 9 }\n"),
            "l.yaml:3:57: modbus.lines.field.address is the address a slave line answers; this line is a master");
  EXPECT_EQ(lines_error("modbus:\n  lines:\n    scada: { device: /dev/ttyS0, role: slave, gateway: { units: [3] } }\n"),
            "l.yaml:3:56: modbus.lines.scada.gateway forwards TCP clients' requests to the slaves on a master line; this "
            "line is a slave");
  EXPECT_EQ(lines_error("modbus:\n  address: 0\n  lines:\n    scada: { device: /dev/ttyS0, role: slave }\n"),
            "l.yaml:4:12: modbus.address 0 cannot be the address of the slave line scada (1..247): set "
            "modbus.lines.scada.address");
}

TEST(LinesConfig, ModbusLinesReplacesRtuModeAndGateway) {
  EXPECT_EQ(lines_error("modbus:\n  rtu: { device: /dev/ttyS0 }\n  lines:\n    scada: { device: /dev/ttyS1, role: slave }\n"),
            "l.yaml:4:5: modbus.lines and modbus.rtu are both set; modbus.rtu is the one line named rtu: move it into "
            "modbus.lines with its role");
  EXPECT_EQ(lines_error("modbus:\n  mode: master\n  lines:\n    field: { device: /dev/ttyS1, role: master }\n"),
            "l.yaml:2:9: modbus.mode is the role of modbus.rtu; each line of modbus.lines has its own role");
  EXPECT_EQ(lines_error("modbus:\n  gateway: { units: [3] }\n  lines:\n    field: { device: /dev/ttyS1, role: master }\n"),
            "l.yaml:2:12: modbus.gateway goes with modbus.rtu; with modbus.lines each master line has its own "
            "(modbus.lines.<name>.gateway)");
  EXPECT_EQ(lines_error("modbus:\n  master: { tcp: 127.0.0.1:1502 }\n  lines:\n    field: { device: /dev/ttyS1, role: master }\n"),
            "l.yaml:2:18: modbus.master.tcp and the master line field are both set; the master drives one line: remove "
            "one of them");
}

TEST(LinesConfig, ACaptureBlockListensToAnotherDeviceThanItsLinesAddress) {
  EXPECT_EQ(lines_error("modbus:\n  lines:\n    scada: { device: /dev/ttyS0, role: slave, address: 9 }\n"
                        "blocks:\n  - { type: capture, device: 9, register: 0x0202, output: 2 }\n"),
            "l.yaml:5:30: a capture block listens to another device; 9 is the bridge's own Modbus address "
            "(modbus.lines.scada.address)");
}

TEST(LinesConfig, ASlaveLineAndAMasterLineServeTogether) {
  const auto c = lines_parse(two_port_modbus +
                             "blocks:\n  - { type: capture, device: 3, register: 0x0202, output: 2 }\n"
                             "  - { type: poll, device: 2, register: 0x10, period: 1s, output: 1 }\n"
                             "  - { type: read, register: 0x0200, source: C+0x00 }\n");
  ASSERT_EQ(c.modbus.lines.size(), 2u);
  EXPECT_EQ(c.modbus.line_of(LineRole::slave), &c.modbus.lines[0]);
  EXPECT_EQ(c.modbus.line_of(LineRole::master), &c.modbus.lines[1]);
  EXPECT_EQ(c.modbus.find_line("field"), &c.modbus.lines[1]);
  EXPECT_EQ(c.modbus.find_line("rtu"), nullptr);
  EXPECT_EQ(c.modbus.mode, ModbusMode::master);
  EXPECT_TRUE(c.modbus.serves_slave_blocks());
  EXPECT_EQ(c.active_blocks().size(), 3u) << "the slave line's blocks and the master line's";
  EXPECT_EQ(c.blocks[0].line, "scada");
  EXPECT_EQ(c.blocks[1].line, "field");
  EXPECT_EQ(c.modbus.shown_name(c.modbus.lines[0]), "scada") << "several lines: names show";
  const auto one = lines_parse("modbus:\n  rtu: { device: /dev/ttyS0 }\n");
  EXPECT_EQ(one.modbus.shown_name(one.modbus.lines[0]), "") << "one line keeps today's port names";
  EXPECT_TRUE(warnings(c).empty());
  ASSERT_TRUE(c.modbus.gateway());
  EXPECT_TRUE(c.modbus.gateway()->routes(2));
}

// Two master lines: each its own blocks and timing, each unit routed to its line's gateway
// with that gateway's settings.
TEST(LinesConfig, TwoMasterLinesEachHaveTheirBlocksAndRouteTheirUnits) {
  const auto c = lines_parse("modbus:\n  lines:\n"
                             "    field: { device: /dev/ttyS1, baud: 9600, role: master, gateway: { units: [5-6] } }\n"
                             "    meters: { device: /dev/ttyS2, baud: 19200, role: master,\n"
                             "              gateway: { units: [9], functions: read } }\n"
                             "blocks:\n"
                             "  - { type: poll, line: field, device: 6, function: 3, register: 0, period: 1s, output: 1 }\n"
                             "  - { type: poll, line: meters, device: 9, function: 3, register: 0, period: 1s, output: 2 }\n"
                             "  - { type: poll, line: meters, device: 10, function: 3, register: 0, period: 1s, output: 3 }\n");
  const auto lines = c.modbus.lines_of(LineRole::master);
  ASSERT_EQ(lines.size(), 2u);
  const auto field = master_setup(c, lines[0]);
  const auto meters = master_setup(c, lines[1]);
  ASSERT_EQ(field.blocks.size(), 1u);
  EXPECT_EQ(field.blocks[0].device, 6);
  ASSERT_EQ(meters.blocks.size(), 2u);
  EXPECT_EQ(meters.blocks[1].device, 10);
  ASSERT_TRUE(field.serial && meters.serial);
  EXPECT_GT(field.serial->frame_gap, meters.serial->frame_gap) << "each line's own t3.5";
  const auto routes = c.modbus.gateway_routes();
  ASSERT_TRUE(routes);
  EXPECT_TRUE(routes->units[5] && routes->units[6] && routes->units[9]);
  EXPECT_FALSE(routes->units[7]);
  EXPECT_FALSE(routes->of(5).reads_only);
  EXPECT_TRUE(routes->of(9).reads_only);
  EXPECT_EQ(routes->gateways[routes->gateway_of[9]].first, "meters");
}

// Several slave lines: each answers as its own address, with its own capture blocks.
TEST(LinesConfig, SeveralSlaveLinesAreServedEachWithItsAddressAndCaptures) {
  const auto c = lines_parse("modbus:\n  address: 1\n  lines:\n    scada: { device: /dev/ttyS0, role: slave }\n"
                              "    panel: { device: /dev/ttyS2, role: slave, address: 2 }\n"
                              "blocks:\n  - { type: capture, line: panel, device: 9, register: 0x10, output: 1 }\n");
  ASSERT_EQ(c.modbus.lines.size(), 2u);
  EXPECT_EQ(c.modbus.lines[0].address, 1);
  EXPECT_EQ(c.modbus.lines[1].address, 2);
  EXPECT_EQ(c.modbus.shown_name(c.modbus.lines[1]), "panel");
  ASSERT_EQ(c.blocks.size(), 1u);
  EXPECT_EQ(c.blocks[0].line, "panel");
}

// A reload keeps a master line whose keys, blocks and gateway are unchanged, wherever they
// moved in the file, and only that line (SPEC §18).
TEST(LinesConfig, AReloadKeepsTheMasterLinesWhoseKeysBlocksAndGatewayAreUnchanged) {
  const std::string field = "    field: { device: /dev/ttyS1, baud: 9600, role: master, gateway: { units: [5-6] } }\n";
  const std::string meters = "    meters: { device: /dev/ttyS2, baud: 19200, role: master, gateway: { units: [9] } }\n";
  const std::string field_poll = "  - { type: poll, line: field, device: 6, function: 3, register: 0, period: 1s, output: 1 }\n";
  const std::string meters_poll = "  - { type: poll, line: meters, device: 9, function: 3, register: 0, period: 1s, output: 2 }\n";
  const auto recipe = [](const std::string& yaml, const char* name) {
    const auto c = lines_parse(yaml);
    return master_recipe(c, c.modbus.find_line(name));
  };
  const auto running = "modbus:\n  lines:\n" + field + meters + "blocks:\n" + field_poll + meters_poll;
  // The same lines and blocks, moved down by a slave line and in another order.
  const auto moved = "modbus:\n  lines:\n    scada: { device: /dev/ttyS0, role: slave }\n" + meters + field + "blocks:\n" +
                     meters_poll + field_poll;
  EXPECT_TRUE(same_master_port(recipe(running, "field"), recipe(moved, "field")));
  EXPECT_TRUE(same_master_port(recipe(running, "meters"), recipe(moved, "meters")));
  EXPECT_FALSE(recipe(running, "field") == recipe(moved, "field")) << "the positions moved";

  // One line's baud, block period, gateway units: only that line changes.
  auto meters_at_9600 = meters;
  meters_at_9600.replace(meters_at_9600.find("19200"), 5, "9600");
  const auto slower = "modbus:\n  lines:\n" + field + meters_at_9600 + "blocks:\n" + field_poll + meters_poll;
  EXPECT_TRUE(same_master_port(recipe(running, "field"), recipe(slower, "field")));
  EXPECT_FALSE(same_master_port(recipe(running, "meters"), recipe(slower, "meters")));
  auto field_poll_2s = field_poll;
  field_poll_2s.replace(field_poll_2s.find("1s"), 2, "2s");
  const auto repolled = "modbus:\n  lines:\n" + field + meters + "blocks:\n" + field_poll_2s + meters_poll;
  EXPECT_FALSE(same_master_port(recipe(running, "field"), recipe(repolled, "field")));
  EXPECT_TRUE(same_master_port(recipe(running, "meters"), recipe(repolled, "meters")));
  auto field_units = field;
  field_units.replace(field_units.find("5-6"), 3, "5-7");
  const auto rerouted = "modbus:\n  lines:\n" + field_units + meters + "blocks:\n" + field_poll + meters_poll;
  EXPECT_FALSE(same_master_port(recipe(running, "field"), recipe(rerouted, "field")));
  EXPECT_TRUE(same_master_port(recipe(running, "meters"), recipe(rerouted, "meters")));

  // From two lines to one, the port's monitor name changes (`master:field` to `master`).
  const auto alone = "modbus:\n  lines:\n" + field + "blocks:\n" + field_poll;
  EXPECT_FALSE(same_master_port(recipe(running, "field"), recipe(alone, "field")));
}

}  // namespace
}  // namespace unima::config
