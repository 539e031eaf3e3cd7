// `unima-bridge map` for a SCADA integrator (issue 30, point 7): the PLC-style numbers
// beside the 0-based address — 3xxxx for the input register (function 4), 4xxxx for the
// holding register (function 3 reads, 6 and 16 write), six digits for the whole map when
// an address is above 9998 — in table, csv and json; and a table within 100 columns.

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <sstream>
#include <string>

#include "tests/integration/cli_under_test.hpp"
#include "tests/integration/harness.hpp"

namespace unima::test {
namespace {

class MapForIntegrators : public ::testing::Test {
 protected:
  CommandResult map(const std::string& yaml, const std::string& format = "") const {
    const auto file = dir.path() / "bridge.yaml";
    test_support::write_file(file, yaml);
    return run(bridge_cli() + " map --config " + file.string() + (format.empty() ? "" : " --format " + format));
  }
  /// The line of `text` that starts with `start`.
  static std::string line_of(const std::string& text, const std::string& start) {
    const auto at = text.find("\n" + start);
    if (at == std::string::npos) return {};
    return text.substr(at + 1, text.find('\n', at + 1) - at - 1);
  }
  TempDir dir;
};

// Every address below 9999: the five-digit numbers. W is written (4xxxx) and read back.
constexpr const char* low_layout =
    "banks: { A: 0x0000, B: 0x0010, C: 0x0020, D1: 0x0100, W: 0x0300, X: 0x0310, S1: 0x0400, S2: 0x0500, S3: 0x0600,\n"
    "         S4: 0x0700, S5: 0x0800, S6: 0x0900, S7: 0x0A00 }\n"
    "devices: { D1: { type: unigen-chp, address: 5 } }\n"
    "state: { file: none }\n";

TEST_F(MapForIntegrators, TheTableShowsTheInputAndHoldingRegisterNumbers) {
  const auto [status, table] = map(low_layout);
  ASSERT_EQ(status, 0) << table;
  EXPECT_EQ(table.substr(0, table.find('\n')).find("address  input  holding  bank"), 0u) << table;
  const auto speed = line_of(table, "0x0101");
  EXPECT_EQ(speed.find("0x0101   30258  40258    D1    R   min-1"), 0u) << speed;
  EXPECT_NE(speed.find("engine_speed"), std::string::npos) << speed;
  EXPECT_EQ(line_of(table, "0x0300").find("0x0300   30769  40769    W     RW"), 0u) << table;
}

TEST_F(MapForIntegrators, AnAddressAbove9998MakesTheWholeMapSixDigit) {
  const auto [status, table] = map("devices: { D1: { type: unigen-chp, address: 5 } }\nstate: { file: none }\n");
  ASSERT_EQ(status, 0) << table;
  EXPECT_EQ(line_of(table, "0x1000").find("0x1000   304097  404097   A"), 0u) << table;  // 0x1000 = 4096
  EXPECT_EQ(line_of(table, "0x3000").find("0x3000   312289  412289   W"), 0u) << table;  // 0x3000 = 12288
}

TEST_F(MapForIntegrators, WithoutFunction3AReadOnlyRegisterHasNoHoldingNumber) {
  const auto [status, table] = map(std::string("modbus: { extensions: { function_3: false } }\n") + low_layout);
  ASSERT_EQ(status, 0) << table;
  EXPECT_EQ(line_of(table, "0x0101").find("0x0101   30258           D1    R"), 0u) << table;
  EXPECT_EQ(line_of(table, "0x0300").find("0x0300   30769  40769    W     RW"), 0u) << table;  // written with 6
}

TEST_F(MapForIntegrators, TheDefaultTableFitsA100ColumnTerminalAndCsvAndJsonKeepEveryField) {
  const auto [status, table] =
      run(bridge_cli() + " map --config " UNIMA_SOURCE_DIR "/config/examples/four-devices.yaml");
  ASSERT_EQ(status, 0) << table;
  std::istringstream lines(table);
  std::string line;
  std::size_t widest = 0;
  while (std::getline(lines, line)) {
    std::size_t characters = 0;
    for (char c : line) characters += (c & 0xC0) != 0x80;
    widest = std::max(widest, characters);
  }
  EXPECT_LE(widest, 100u) << table;
  // A long label is cut in the table and whole in csv and json.
  const auto oil = line_of(table, "0x1121");
  EXPECT_NE(oil.find("oil_temperature"), std::string::npos) << oil;

  const auto csv = run(bridge_cli() + " map --format csv --config " UNIMA_SOURCE_DIR "/config/examples/four-devices.yaml");
  ASSERT_EQ(csv.status, 0) << csv.output;
  EXPECT_EQ(csv.output.substr(0, csv.output.find('\n')),
            "address,bank,offset,id,label,kind,unit,scale,access,source,input_register,holding_register");
  EXPECT_NE(csv.output.find("\n0x1121,D1,0x21,oil_temperature,Teplota oleje,analog,°C,0.1,R,,304386,404386\n"),
            std::string::npos)
      << csv.output;

  const auto json = run(bridge_cli() + " map --format json --config " UNIMA_SOURCE_DIR "/config/examples/four-devices.yaml");
  ASSERT_EQ(json.status, 0) << json.output;
  const auto rows = nlohmann::json::parse(json.output);
  const auto oil_row = std::find_if(rows.begin(), rows.end(), [](const auto& row) { return row["address"] == "0x1121"; });
  ASSERT_NE(oil_row, rows.end());
  EXPECT_EQ((*oil_row)["input_register"], 304386);
  EXPECT_EQ((*oil_row)["holding_register"], 404386);
  EXPECT_EQ((*oil_row)["label"], "Teplota oleje");
}

}  // namespace
}  // namespace unima::test
