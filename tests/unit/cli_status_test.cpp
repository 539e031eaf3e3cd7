// `unima-bridge status`' panel (cli::render_status_panel) of the daemon's own document
// (tests/golden/status_slave.json, kept by the integration test StatusKeys with every part
// on), read through the typed parts: the front panel, the indicators and the ports' table
// as an operator reads them.

#include <gtest/gtest.h>

#include <filesystem>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "cli/cli_status.hpp"
#include "tests/support/temp_files.hpp"

namespace unima::cli {
namespace {

nlohmann::json golden_slave() {
  return nlohmann::json::parse(
      test_support::read_file(std::filesystem::path(UNIMA_SOURCE_DIR) / "tests" / "golden" / "status_slave.json"));
}

bool has_line(const std::string& text, const std::string& line) { return text.find("\n" + line + "\n") != std::string::npos; }

TEST(CliStatus, ThePanelShowsTheFrontPanelIndicatorsAndPortsOfTheDocument) {
  const auto document = golden_slave();
  const auto text = render_status_panel(document.get<status::Document>());
  // The golden document is rewritten with the daemon's own time and port when its keys
  // change (UNIMA_UPDATE_GOLDEN): those two are read from it.
  const auto indicator_time = document["indicators"][0]["time"].get<std::string>();
  const auto tcp_listen = document["ports"][0]["listen"].get<std::string>();
  EXPECT_TRUE(text.starts_with("unima-bridge  slave mode  Modbus address 1  UnimaBUS address 5  up 0h00m00s\n")) << text;
  const auto& modbus = document["modbus"];
  EXPECT_TRUE(has_line(text, fmt::format("  Modbus    [{}]  last frame sent {:.1f} s ago", modbus["active"].get<bool>() ? '*' : ' ',
                                         modbus["last_ms_ago"].get<double>() / 1000)))
      << text;
  EXPECT_TRUE(has_line(text, "  UnimaBUS  [ ]  no telegram received yet (feed transport)")) << text;
  EXPECT_TRUE(has_line(text, "  Error     [ ]  no fault in the last 2 s")) << text;
  EXPECT_TRUE(has_line(text, "  D1 [ ] unigen-chp@5   D2 -   D3 -   D4 -  ")) << text;
  EXPECT_TRUE(has_line(text, "  S1 [ ] S2 [ ] S3 [ ] S4 [ ] S5 [ ] S6 [ ] S7 [ ]")) << text;
  EXPECT_TRUE(has_line(text, "  1  Ad=1   Reg=0x0100  0x7FFF (32767)  read   " + indicator_time)) << text;
  EXPECT_TRUE(has_line(text, "  tcp             1       1       0       0       0       0       0        0        1  " + tcp_listen))
      << text;
  const auto written = document["monitor"]["written"].get<int>();  // the writer thread's count when the golden was taken
  EXPECT_TRUE(has_line(text, fmt::format("            {} {} written, {} dropped", written, written == 1 ? "line" : "lines",
                                         document["monitor"]["dropped"].get<int>())))
      << text;
}

// A count of one is said in the singular.
TEST(CliStatus, OneOfAThingIsSaidInTheSingular) {
  auto document = golden_slave();
  document["state"]["records"] = 1;
  document["state"]["syncs"] = 1;
  document["monitor"]["written"] = 1;
  const auto text = render_status_panel(document.get<status::Document>());
  EXPECT_NE(text.find(": 1 value recorded in 1 sync, 0 failed\n"), std::string::npos) << text;
  EXPECT_TRUE(has_line(text, "            1 line written, 0 dropped")) << text;
  document["state"]["records"] = 2;
  EXPECT_NE(render_status_panel(document.get<status::Document>()).find(": 2 values recorded in 1 sync"), std::string::npos);
}

// Which config runs is shown once a config came from afar; a bridge that only ever ran its
// operator's file shows what it always showed.
TEST(CliStatus, AConfigFromAfarIsShownWithHowTheLastChangeEnded) {
  auto document = golden_slave();
  EXPECT_EQ(render_status_panel(document.get<status::Document>()).find("  Config"), std::string::npos);
  document["config_in_force"] = {{"source", "mqtt"}, {"file", "/var/lib/unima-bridge/remote-config/000003.yaml"},
                                 {"sha256", "696a4156a99ae4122c62793e8e518508a2fa791020f9c86475701dee260aa309"},
                                 {"number", 3}, {"by", "fleet"}, {"applied_at", "2026-11-29T22:57:55.433190Z"},
                                 {"last", {{"id", "ab"}, {"result", "rolled_back"}, {"reason", "the MQTT broker has not accepted the bridge"},
                                           {"source", "cli"}, {"by", "root"}, {"at", "2026-11-29T23:01:00.000000Z"}}}};
  const auto text = render_status_panel(document.get<status::Document>());
  EXPECT_TRUE(has_line(text, "  Config    remote config 3 from mqtt by fleet at 2026-11-29T22:57:55.433190Z (sha256 696a4156a99a…)"))
      << text;
  EXPECT_TRUE(has_line(text, "            last change: rolled_back (cli by root at 2026-11-29T23:01:00.000000Z): the MQTT broker "
                             "has not accepted the bridge"))
      << text;
}

// On a terminal: a lit LED green, the Error LED and what needs looking at red; into a
// pipe (the default style) not one escape sequence.
TEST(CliStatus, OnATerminalLitLedsAreGreenAndFaultsRed) {
  auto document = golden_slave();
  document["modbus"]["active"] = true;
  document["error"] = true;
  document["ports"] = nlohmann::json::parse(R"([{"port": "tcp", "transactions": 9, "Done": 7, "Err02": 2, "clients": 1}])");
  document["mqtt"]["connected"] = false;
  const auto coloured = render_status_panel(document.get<status::Document>(), PanelStyle{true});
  EXPECT_NE(coloured.find("  Modbus    \033[32m[*]\033[0m  "), std::string::npos) << coloured;
  EXPECT_NE(coloured.find("  Error     \033[1;31m[*]\033[0m  \033[1;31mModbus fault"), std::string::npos) << coloured;
  EXPECT_NE(coloured.find("\033[1;31m      2\033[0m"), std::string::npos) << "Err02's count: " << coloured;
  EXPECT_NE(coloured.find("\033[1;31mMQTT        not connected to "), std::string::npos) << coloured;
  const auto plain = render_status_panel(document.get<status::Document>());
  EXPECT_EQ(plain.find('\033'), std::string::npos) << plain;
  EXPECT_TRUE(has_line(plain, "  tcp             9       7       -       -       2       -       -        -        1")) << plain;
}

// A figure a port does not have is a dash, not a 0 that was never counted.
TEST(CliStatus, APortWithoutClientsOrAStateShowsADash) {
  auto document = golden_slave();
  document["ports"] = nlohmann::json::parse(R"([{"port": "rtu", "transactions": 2, "Done": 2}])");
  EXPECT_TRUE(has_line(render_status_panel(document.get<status::Document>()),
                       "  rtu             2       2       -       -       -       -       -        -        -"));
}

// A row per RS-485 line (SPEC §18), and the ports' table as wide as a line's port name.
TEST(CliStatus, EachLineHasARowAndItsPortsAName) {
  auto document = golden_slave();
  document["lines"] = nlohmann::json::parse(R"([
    {"line": "scada", "role": "slave", "device": "/dev/ttyRS485-0", "settings": "19200 8E1", "open": true,
     "frames_sent": 10, "frames_received": 12, "errors": 0, "queue": 0},
    {"line": "field", "role": "master", "device": "/dev/ttyRS485-1", "settings": "9600 8N1", "open": false,
     "frames_sent": 30, "frames_received": 27, "errors": 3, "queue": 4}])");
  document["ports"] = nlohmann::json::parse(R"([{"port": "rtu:scada", "transactions": 2, "Done": 2},
                                                {"port": "master:field", "transactions": 30, "Done": 27, "Timeout": 3}])");
  const auto text = render_status_panel(document.get<status::Document>());
  EXPECT_TRUE(has_line(text, "Line        role    device           settings     open      sent  received   errors  queue")) << text;
  EXPECT_TRUE(has_line(text, "  scada     slave   /dev/ttyRS485-0  19200 8E1    yes         10        12        0      0")) << text;
  EXPECT_TRUE(has_line(text, "  field     master  /dev/ttyRS485-1  9600 8N1     no          30        27        3      4")) << text;
  EXPECT_TRUE(has_line(text, "Port            frames    Done  Not4Me   Err01   Err02   Err03   Err04  Timeout  clients")) << text;
  EXPECT_TRUE(has_line(text, "  rtu:scada           2       2       -       -       -       -       -        -        -")) << text;
  EXPECT_TRUE(has_line(text, "  master:field       30      27       -       -       -       -       -        3        -")) << text;
  const auto coloured = render_status_panel(document.get<status::Document>(), PanelStyle{true});
  EXPECT_NE(coloured.find("\033[1;31mno  \033[0m"), std::string::npos) << coloured;
  EXPECT_NE(coloured.find("\033[1;31m       3\033[0m"), std::string::npos) << coloured;
}

// `status` says so (an unexpected document) rather than draw a panel of zeros.
TEST(CliStatus, ADocumentWithoutAPartIsAnError) {
  auto document = golden_slave();
  document.erase("devices");
  EXPECT_THROW(render_status_panel(document.get<status::Document>()), MissingPart);
}

}  // namespace
}  // namespace unima::cli
