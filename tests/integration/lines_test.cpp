// Several lines (SPEC §18, issue 39): one daemon answers the SCADA on one RS-485 line and
// polls the foreign slaves on another, whose gateway TCP clients reach. Two pseudo-terminal
// pairs: the foreign-slave simulator on the master line, a libmodbus RTU master (the
// SCADA) through socat on the slave line.

#include <algorithm>
#include <atomic>
#include <thread>
#include <optional>

#include "tests/integration/cli_under_test.hpp"
#include "tests/integration/gateway_fixture.hpp"
#include "tests/integration/rtu_line.hpp"
#include "tests/support/peers/http_exchange.hpp"

namespace unima::test {
namespace {

class LinesTest : public GatewayTest {
 protected:
  /// The stepper driver polled every 200 ms on the `field` line (its SUBDIVISION, 8, into
  /// output 1), the PLC behind its gateway; the SCADA's line `scada` at 19200 baud.
  void start_two_lines() {
    ASSERT_TRUE(scada_link->ready());
    simulate({"5=wecon-lx5v", "6=stepper-driver"});
    config.mode.clear();
    config.line.clear();
    config.master = "retries: 1, response_timeout: 300ms";
    config.blocks = "  - { type: poll, line: field, device: 6, profile: stepper-driver, point: SUBDIVISION, period: 200ms, "
                    "output: 1 }\n" + extra_blocks;
    config.modbus_extra = lines_yaml();
    start();
  }
  std::string lines_yaml() const {
    return "  lines:\n"
           "    scada: { device: " + bridge_end.string() + ", baud: 19200, role: slave }\n"
           "    field: { device: " + sim->pty() + ", baud: " + std::to_string(line_baud) +
           ", role: master, gateway: { units: [5], timeout: 300ms } }\n" + more_lines;
  }
  std::string more_lines;    // more lines of modbus.lines
  std::string extra_blocks;  // more blocks
  /// The row of `name` in the status document's "lines"; null when there is none.
  nlohmann::json line_row(const nlohmann::json& s, const std::string& name) const {
    for (const auto& row : s.value("lines", nlohmann::json::array()))
      if (row["line"] == name) return row;
    return nullptr;
  }
  std::filesystem::path scada_end = dir.path() / "scada";
  std::filesystem::path bridge_end = dir.path() / "bridge";
  std::optional<SocatLink> scada_link{std::in_place, scada_end, bridge_end};
};

TEST_F(LinesTest, TheScadaPollsTheSlaveLineWhileAClientReachesAForeignSlaveOnTheMasterLine) {
  start_two_lines();
  ASSERT_TRUE(output_becomes(1, 8)) << diagnostics();  // the master line polls
  ASSERT_EQ(sim->control("set 5 0 4660"), "ok");       // the PLC's D0 = 0x1234
  RtuMaster scada(scada_end, 19200);
  ASSERT_TRUE(scada.connected());
  auto client = Socket::tcp(config.modbus_port);
  for (int round = 0; round < 10; ++round) {
    EXPECT_EQ(scada.read_input(c_bank, 1), std::vector<std::uint16_t>{8}) << "round " << round << "\n" << diagnostics();
    const auto answer = ask(client, static_cast<std::uint16_t>(0x5100 + round), plc, {0x03, 0x00, 0x00, 0x00, 0x01});
    ASSERT_TRUE(answer) << "round " << round << "\n" << diagnostics();
    EXPECT_EQ(answer->pdu, (Bytes{0x03, 0x02, 0x12, 0x34})) << hex(answer->pdu);
  }
  EXPECT_EQ(heard(rtu_frame(plc, {0x03, 0x00, 0x00, 0x00, 0x01})), 10u) << "every request on the master line, once";
  EXPECT_TRUE(scada.write(w_bank + 1, 77)) << "the slave line takes the SCADA's writes";
  ModbusClient tcp(config.modbus_port);
  EXPECT_EQ(tcp.read_input(w_bank + 1, 1), std::vector<std::uint16_t>{77});

  // Each line's port is named by the line, as there are two (SPEC §18).
  std::string log;
  ASSERT_TRUE(eventually([&] {
    log = read_file(monitor_log());
    return log.find(" rtu:scada ") != std::string::npos && log.find(" master:field ") != std::string::npos &&
           log.find(" gw:field:127.0.0.1:") != std::string::npos;
  })) << log;
  EXPECT_EQ(log.find(" rtu "), std::string::npos) << log;
  EXPECT_EQ(log.find(" master "), std::string::npos) << log;
  EXPECT_EQ(log.find(" gw:127.0.0.1:"), std::string::npos) << log;

  // The status document's port rows, by line.
  const auto s = status();
  std::vector<std::string> ports;
  for (const auto& port : s["ports"]) ports.push_back(port["port"].get<std::string>());
  EXPECT_NE(std::find(ports.begin(), ports.end(), "rtu:scada"), ports.end()) << s.dump();
  EXPECT_NE(std::find(ports.begin(), ports.end(), "master:field"), ports.end()) << s.dump();

  // A row per line: its role, device, settings, and what it carried.
  const auto scada_row = line_row(s, "scada");
  ASSERT_TRUE(scada_row.is_object()) << s.dump();
  EXPECT_EQ(scada_row["role"], "slave");
  EXPECT_EQ(scada_row["device"], bridge_end.string());
  EXPECT_EQ(scada_row["settings"], "19200 8N1");
  EXPECT_EQ(scada_row["open"], true);
  EXPECT_GE(scada_row["frames_received"].get<int>(), 11) << "ten reads and a write";
  EXPECT_GE(scada_row["frames_sent"].get<int>(), 11);
  EXPECT_EQ(scada_row["errors"], 0);
  const auto field_row = line_row(s, "field");
  ASSERT_TRUE(field_row.is_object()) << s.dump();
  EXPECT_EQ(field_row["role"], "master");
  EXPECT_EQ(field_row["device"], sim->pty());
  EXPECT_GE(field_row["frames_sent"].get<int>(), 10) << "the forwarded reads and the polls";
  EXPECT_EQ(field_row["frames_sent"], field_row["frames_received"].get<int>() + field_row["errors"].get<int>());

  // `unima-bridge status`: the lines' table.
  const auto panel = run(bridge_cli() + " status --socket " + config.status_socket).output;
  EXPECT_NE(panel.find("\n  scada     slave   " + bridge_end.string()), std::string::npos) << panel;
  EXPECT_NE(panel.find("\n  field     master  " + sim->pty()), std::string::npos) << panel;
}

// The SCADA's line unplugged (its device gone) and plugged back: the master line and the
// gateway go on meanwhile, the status says the line is not open, and the SCADA is served
// again once its device is back.
TEST_F(LinesTest, AnUnpluggedSlaveLineStopsNothingElseAndServesAgainWhenPluggedBack) {
  start_two_lines();
  ASSERT_TRUE(output_becomes(1, 8)) << diagnostics();
  ASSERT_EQ(sim->control("set 5 0 4660"), "ok");
  scada_link.reset();  // socat gone: the bridge's end of the line with it
  ASSERT_TRUE(eventually([&] { return line_row(status(), "scada")["open"] == false; }, 10s)) << status().dump(1);
  auto client = Socket::tcp(config.modbus_port);
  const auto polls_before = polls();
  for (std::uint16_t round = 0; round < 5; ++round) {
    const auto answer = ask(client, round, plc, {0x03, 0x00, 0x00, 0x00, 0x01});
    ASSERT_TRUE(answer) << "round " << round << "\n" << diagnostics();
    EXPECT_EQ(answer->pdu, (Bytes{0x03, 0x02, 0x12, 0x34})) << hex(answer->pdu);
  }
  EXPECT_TRUE(eventually([&] { return polls() > polls_before; })) << "the master line polls on";
  EXPECT_EQ(line_row(status(), "field")["open"], true);

  scada_link.emplace(scada_end, bridge_end);
  ASSERT_TRUE(scada_link->ready());
  ASSERT_TRUE(eventually([&] { return line_row(status(), "scada")["open"] == true; }, 15s)) << status().dump(1);
  RtuMaster scada(scada_end, 19200);
  ASSERT_TRUE(scada.connected());
  EXPECT_EQ(scada.read_input(c_bank, 1), std::vector<std::uint16_t>{8}) << diagnostics();
}

// The page has a box per line; /metrics counts each line by its label.
TEST_F(LinesTest, ThePageHasABoxPerLineAndMetricsALineLabel) {
  const auto http_port = free_port();
  config.extra += "http: { listen: 127.0.0.1, port: " + std::to_string(http_port) + " }\n";
  start_two_lines();
  ASSERT_TRUE(wait_for_port(http_port)) << diagnostics();
  ASSERT_TRUE(output_becomes(1, 8)) << diagnostics();
  const auto metrics = test_support::http_get(http_port, "/metrics").body;
  EXPECT_NE(metrics.find("unima_bridge_line_open{line=\"scada\",role=\"slave\"} 1\n"), std::string::npos) << metrics;
  EXPECT_NE(metrics.find("unima_bridge_line_frames_sent_total{line=\"field\",role=\"master\"} "), std::string::npos) << metrics;

  const auto command = std::string(UNIMA_SOURCE_DIR) + "/tests/integration/browser/page_in_chromium.py --url http://127.0.0.1:" +
                       std::to_string(http_port) + "/ --serial-line 'scada=19200 8N1' --serial-line 'field=" + sim->pty() +
                       "' --timeout 30 2>&1";
  const auto result = run(command);
  ASSERT_EQ(result.status, 0) << result.output;
  const auto shown = nlohmann::json::parse(result.output.substr(result.output.rfind("{\"ok\"")), nullptr, false);
  ASSERT_TRUE(shown.contains("serial_lines")) << result.output;
  const auto& boxes = shown["serial_lines"];
  EXPECT_EQ(boxes["scada"]["open"], "true") << boxes;
  EXPECT_NE(boxes["scada"]["text"].get<std::string>().find("scada: slave"), std::string::npos) << boxes;
  EXPECT_NE(boxes["field"]["text"].get<std::string>().find("field: master"), std::string::npos) << boxes;
}

// Two slave lines (a SCADA and an operator panel, each its own RS-485 port) and the master
// line: each slave line answers as its own address and counts on its own; a reload that
// changes the panel's line reopens it alone, the SCADA's keeps its port and its counters.
TEST_F(LinesTest, TwoSlaveLinesAnswerEachAsItsAddressAndAReloadOfOneLeavesTheOther) {
  const auto panel_end = dir.path() / "panel";
  const auto panel_bridge_end = dir.path() / "panel-bridge";
  SocatLink panel_link(panel_end, panel_bridge_end);
  ASSERT_TRUE(panel_link.ready());
  const auto panel_line = [&](unsigned baud) {
    return "    panel: { device: " + panel_bridge_end.string() + ", baud: " + std::to_string(baud) +
           ", role: slave, address: 2 }\n";
  };
  more_lines = panel_line(9600);
  start_two_lines();
  ASSERT_TRUE(output_becomes(1, 8)) << diagnostics();
  RtuMaster scada(scada_end, 19200, 1);
  ASSERT_TRUE(scada.connected());
  {
    RtuMaster panel(panel_end, 9600, 2);
    ASSERT_TRUE(panel.connected());
    for (int round = 0; round < 5; ++round) {
      EXPECT_EQ(scada.read_input(c_bank, 1), std::vector<std::uint16_t>{8}) << "round " << round << "\n" << diagnostics();
      EXPECT_EQ(panel.read_input(c_bank, 1), std::vector<std::uint16_t>{8}) << "round " << round << "\n" << diagnostics();
    }
  }
  {
    RtuMaster panel_as_1(panel_end, 9600, 1);
    ASSERT_TRUE(panel_as_1.connected());
    EXPECT_FALSE(panel_as_1.read_input(c_bank, 1)) << "address 1 is the SCADA line's, not the panel's";
  }

  auto s = status();
  const auto scada_before = line_row(s, "scada");
  ASSERT_TRUE(scada_before.is_object()) << s.dump(1);
  EXPECT_GE(scada_before["frames_received"].get<int>(), 5);
  EXPECT_GE(line_row(s, "panel")["frames_received"].get<int>(), 6);
  std::vector<std::string> ports;
  for (const auto& port : s["ports"]) ports.push_back(port["port"].get<std::string>());
  EXPECT_NE(std::find(ports.begin(), ports.end(), "rtu:panel"), ports.end()) << s.dump();

  // The panel's line to 19200 baud: reopened; the SCADA's untouched.
  more_lines = panel_line(19200);
  config.modbus_extra = lines_yaml();
  daemon->rewrite_config(config.yaml());
  daemon->signal(SIGHUP);
  ASSERT_TRUE(daemon->wait_for_log("reloaded")) << daemon->log();
  s = status();
  EXPECT_EQ(line_row(s, "panel")["settings"], "19200 8N1") << s.dump(1);
  EXPECT_EQ(line_row(s, "panel")["frames_received"], 0) << "a reopened line counts anew";
  EXPECT_GE(line_row(s, "scada")["frames_received"].get<int>(), scada_before["frames_received"].get<int>())
      << "the SCADA's line kept its counters";
  EXPECT_EQ(scada.read_input(c_bank, 1), std::vector<std::uint16_t>{8}) << "the SCADA's connection was never closed";
  RtuMaster faster_panel(panel_end, 19200, 2);
  ASSERT_TRUE(faster_panel.connected());
  EXPECT_EQ(faster_panel.read_input(c_bank, 1), std::vector<std::uint16_t>{8}) << diagnostics();
}

// Two master lines, each its own simulator: the bridge polls a device on each, and a TCP
// client reaches unit 5 through `field` and unit 9 through `meters` — each answered by the
// slave on its own line, each line counted on its own.
TEST_F(LinesTest, TwoMasterLinesEachPollTheirDevicesAndForwardTheirUnits) {
  TempDir meters_dir;
  SlaveSim meters(meters_dir, {"9=wecon-lx5v"});
  ASSERT_TRUE(meters.ready());
  more_lines = "    meters: { device: " + meters.pty() + ", baud: " + std::to_string(line_baud) +
               ", role: master, gateway: { units: [9], timeout: 300ms } }\n";
  extra_blocks = "  - { type: poll, line: meters, device: 9, profile: wecon-lx5v, operand: D1, period: 200ms, output: 2 }\n";
  ASSERT_EQ(meters.control("set 9 1 4242"), "ok");
  start_two_lines();
  ASSERT_TRUE(output_becomes(1, 8)) << "the field line's poll\n" << diagnostics();
  ASSERT_TRUE(output_becomes(2, 4242)) << "the meters line's poll\n" << diagnostics();
  ASSERT_EQ(sim->control("set 5 0 4660"), "ok");
  ASSERT_EQ(meters.control("set 9 0 22136"), "ok");
  auto client = Socket::tcp(config.modbus_port);
  for (std::uint16_t round = 0; round < 5; ++round) {
    const auto field_answer = ask(client, round, plc, {0x03, 0x00, 0x00, 0x00, 0x01});
    ASSERT_TRUE(field_answer) << diagnostics();
    EXPECT_EQ(field_answer->pdu, (Bytes{0x03, 0x02, 0x12, 0x34})) << hex(field_answer->pdu);
    const auto meters_answer = ask(client, static_cast<std::uint16_t>(100 + round), 9, {0x03, 0x00, 0x00, 0x00, 0x01});
    ASSERT_TRUE(meters_answer) << diagnostics();
    EXPECT_EQ(meters_answer->pdu, (Bytes{0x03, 0x02, 0x56, 0x78})) << hex(meters_answer->pdu);
  }
  EXPECT_EQ(heard(rtu_frame(9, {0x03, 0x00, 0x00, 0x00, 0x01})), 0u) << "unit 9 never on the field line";

  const auto s = status();
  const auto field_row = line_row(s, "field");
  const auto meters_row = line_row(s, "meters");
  ASSERT_TRUE(field_row.is_object() && meters_row.is_object()) << s.dump(1);
  EXPECT_EQ(meters_row["role"], "master");
  EXPECT_EQ(meters_row["device"], meters.pty());
  EXPECT_GE(meters_row["frames_sent"].get<int>(), 6) << "five forwarded reads and a poll";
  EXPECT_GE(field_row["frames_sent"].get<int>(), 6);
  std::vector<std::string> ports;
  for (const auto& port : s["ports"]) ports.push_back(port["port"].get<std::string>());
  EXPECT_NE(std::find(ports.begin(), ports.end(), "master:meters"), ports.end()) << s.dump();
  EXPECT_NE(std::find(ports.begin(), ports.end(), "master:field"), ports.end()) << s.dump();
  EXPECT_NE(s["gateway"]["routes"].get<std::string>().find("9"), std::string::npos) << s["gateway"].dump();
}

// The field line unplugged (the simulator and its pty gone) and plugged back: the SCADA's
// line serves on, the gateway answers 0x0B for the unit it cannot reach, the status says
// the line is not open, and the master polls and forwards again once the device is back.
TEST_F(LinesTest, AnUnpluggedMasterLineStopsNothingElseAndPollsAgainWhenPluggedBack) {
  start_two_lines();
  ASSERT_TRUE(output_becomes(1, 8)) << diagnostics();
  RtuMaster scada(scada_end, 19200);
  ASSERT_TRUE(scada.connected());
  // The link goes first: a pty number freed by the simulator may be another test's next,
  // and the bridge must not reopen that one through a link left behind.
  std::filesystem::remove(sim->pty());
  sim.reset();
  ASSERT_TRUE(eventually([&] { return line_row(status(), "field")["open"] == false; }, 10s))
      << status().dump(1) << "\n" << daemon->log();
  EXPECT_TRUE(daemon->wait_for_log(" lost: ")) << daemon->log();
  auto client = Socket::tcp(config.modbus_port);
  for (std::uint16_t round = 0; round < 3; ++round) {
    EXPECT_TRUE(scada.read_input(c_bank, 1)) << "round " << round << "\n" << daemon->log();
    EXPECT_TRUE(scada.write(w_bank + 1, static_cast<std::uint16_t>(100 + round))) << daemon->log();
    const auto answer = ask(client, round, plc, {0x03, 0x00, 0x00, 0x00, 0x01});
    ASSERT_TRUE(answer) << "round " << round << "\n" << daemon->log();
    EXPECT_EQ(answer->pdu, (Bytes{0x83, 0x0B})) << "nothing on the line can answer: " << hex(answer->pdu);
  }
  ModbusClient tcp(config.modbus_port);
  EXPECT_EQ(tcp.read_input(w_bank + 1, 1), std::vector<std::uint16_t>{102}) << "the SCADA's writes reached the banks";
  EXPECT_EQ(line_row(status(), "scada")["open"], true);

  simulate({"5=wecon-lx5v", "6=stepper-driver"});  // at the same path
  ASSERT_TRUE(eventually([&] { return line_row(status(), "field")["open"] == true; }, 15s))
      << status().dump(1) << "\n" << daemon->log();
  EXPECT_TRUE(daemon->wait_for_log("modbus master: rtu " + sim->pty() + " " + std::to_string(line_baud) + " 8N1 back"))
      << daemon->log();
  EXPECT_TRUE(eventually([&] { return polls() > 0; })) << "the master polls the device again\n" << diagnostics();
  ASSERT_EQ(sim->control("set 5 0 4660"), "ok");
  const auto answer = ask(client, 99, plc, {0x03, 0x00, 0x00, 0x00, 0x01});
  ASSERT_TRUE(answer) << diagnostics();
  EXPECT_EQ(answer->pdu, (Bytes{0x03, 0x02, 0x12, 0x34})) << hex(answer->pdu);
}

// Two master lines, a client keeping `field` busy through its gateway; a reload changes the
// `meters` line's poll alone: `meters` is reopened and counts anew, `field` keeps its port,
// its queue and its counters, and not one of the busy client's requests goes wrong.
TEST_F(LinesTest, AReloadOfOneMasterLineLeavesTheOtherBusyLineItsPortQueueAndCounters) {
  TempDir meters_dir;
  SlaveSim meters(meters_dir, {"9=wecon-lx5v"});
  ASSERT_TRUE(meters.ready());
  more_lines = "    meters: { device: " + meters.pty() + ", baud: " + std::to_string(line_baud) +
               ", role: master, gateway: { units: [9], timeout: 300ms } }\n";
  const auto meters_poll = [](const char* period) {
    return std::string("  - { type: poll, line: meters, device: 9, profile: wecon-lx5v, operand: D1, period: ") + period +
           ", output: 2 }\n";
  };
  extra_blocks = meters_poll("200ms");
  ASSERT_EQ(meters.control("set 9 1 4242"), "ok");
  start_two_lines();
  ASSERT_TRUE(output_becomes(2, 4242)) << diagnostics();
  ASSERT_EQ(sim->control("set 5 0 4660"), "ok");
  auto meters_client = Socket::tcp(config.modbus_port);
  for (std::uint16_t round = 0; round < 12; ++round)
    ASSERT_TRUE(ask(meters_client, round, 9, {0x03, 0x00, 0x00, 0x00, 0x01})) << diagnostics();

  // The busy client: bounded by a count and by the flag.
  std::atomic<bool> stop{false};
  std::atomic<int> right{0};
  std::atomic<int> wrong{0};
  std::string first_wrong;  // read after the join
  std::thread busy([&] {
    auto client = Socket::tcp(config.modbus_port);
    for (std::uint16_t id = 0; id < 5000 && !stop; ++id) {
      const auto answer = ask(client, id, plc, {0x03, 0x00, 0x00, 0x00, 0x01});
      if (answer && answer->transaction == id && answer->pdu == Bytes{0x03, 0x02, 0x12, 0x34}) {
        ++right;
      } else {
        if (wrong++ == 0) first_wrong = answer ? hex(answer->pdu) : std::string("no answer");
      }
    }
  });
  const auto busy_until = [&](int count) { return eventually([&] { return right >= count || wrong > 0; }, 10s); };
  EXPECT_TRUE(busy_until(20));
  auto s = status();
  const auto field_before = line_row(s, "field")["frames_sent"].get<int>();
  const auto meters_before = line_row(s, "meters")["frames_sent"].get<int>();
  EXPECT_GE(meters_before, 12) << s.dump(1);

  const auto at = config.blocks.find(extra_blocks);
  ASSERT_NE(at, std::string::npos);
  config.blocks.replace(at, extra_blocks.size(), meters_poll("300ms"));
  daemon->rewrite_config(config.yaml());
  daemon->signal(SIGHUP);
  const auto reloaded = daemon->wait_for_log("reloaded");
  const auto right_at_reload = right.load();
  EXPECT_TRUE(busy_until(right_at_reload + 20)) << "the field line served on through the reload";
  stop = true;
  busy.join();
  ASSERT_TRUE(reloaded) << daemon->log();
  EXPECT_EQ(wrong, 0) << "wrong answers, the first: " << first_wrong;

  s = status();
  EXPECT_GT(line_row(s, "field")["frames_sent"].get<int>(), field_before + 20) << "field kept its counters\n" << s.dump(1);
  EXPECT_LT(line_row(s, "meters")["frames_sent"].get<int>(), meters_before) << "meters counts anew\n" << s.dump(1);
  EXPECT_NE(daemon->log().find("modbus master: line field unchanged, kept with its queue and counters"), std::string::npos) << daemon->log();
  EXPECT_EQ(daemon->log().find("modbus master: line meters unchanged"), std::string::npos) << daemon->log();
  ASSERT_EQ(meters.control("set 9 1 4343"), "ok");
  EXPECT_TRUE(output_becomes(2, 4343)) << "the new meters poll\n" << diagnostics();
}

// docs/lines.md's two-port site (a Revolution Pi Compact) is what `check` accepts as written.
TEST(LinesDoc, CheckAcceptsTheTwoPortSiteAsWritten) {
  const auto guide = read_file(std::string(UNIMA_SOURCE_DIR) + "/docs/lines.md");
  const std::string fence = "```yaml\n";
  const auto begin = guide.find(fence);
  ASSERT_NE(begin, std::string::npos);
  const auto end = guide.find("```\n", begin + fence.size());
  ASSERT_NE(end, std::string::npos);
  TempDir dir;
  const auto file = dir.path() / "bridge.yaml";
  test_support::write_file(file, guide.substr(begin + fence.size(), end - begin - fence.size()));
  const auto [status, output] = run(bridge_cli() + " check --config " + file.string());
  EXPECT_EQ(status, 0) << output;
  EXPECT_NE(output.find("line scada: slave, /dev/ttyRS485-0 19200 baud 8E1, t3.5 = "), std::string::npos) << output;
  EXPECT_NE(output.find("line field: master, /dev/ttyRS485-1 9600 baud 8N1, t3.5 = "), std::string::npos) << output;
  EXPECT_NE(output.find(", gateway units 5-6\n"), std::string::npos) << output;
  EXPECT_NE(output.find("master: field /dev/ttyRS485-1 9600 baud"), std::string::npos) << output;
  EXPECT_NE(output.find("  3 blocks in 3 requests"), std::string::npos) << "the master line's blocks\n" << output;
  // The warnings a machine without the ports gives, and no other.
  std::size_t warnings = 0;
  for (auto at = output.find("warning"); at != std::string::npos; at = output.find("warning", at + 1)) ++warnings;
  EXPECT_NE(output.find("warning: modbus.lines.scada.device: /dev/ttyRS485-0: "), std::string::npos) << output;
  EXPECT_NE(output.find("warning: modbus.lines.field.device: /dev/ttyRS485-1: "), std::string::npos) << output;
  EXPECT_EQ(warnings, 2u) << output;
}

}  // namespace
}  // namespace unima::test
