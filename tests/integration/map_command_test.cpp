// `unima-bridge map` for a SCADA integrator (issue 30, point 7): the PLC-style numbers
// beside the 0-based address — 3xxxx for the input register (function 4), 4xxxx for the
// holding register (function 3 reads, 6 and 16 write), six digits for the whole map when
// an address is above 9998 — in table, csv and json; and a table within 100 columns.

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <sstream>
#include <string>
#include <vector>

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
            "address,bank,offset,id,label,kind,unit,scale,access,source,input_register,holding_register,data_type,part,"
            "bits,partner,word_order");  // issue 44: the pairs' and bytes' columns after the old ones
  EXPECT_NE(csv.output.find("\n0x1121,D1,0x21,oil_temperature,Teplota oleje,analog,°C,0.1,R,,304386,404386,int16,word,"
                            ",,\n"),
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

// A SCADA's tag import reads the csv (issue 44, finding 5): every row one tag that is right
// on its own, a row per byte of a byte pair, a 32-bit pair's halves or the pair as one.
class MapCsvForATagImport : public ::testing::Test {
 protected:
  using Record = std::vector<std::string>;
  struct Csv {
    Record header;
    std::vector<Record> records;
    /// The cell of `record` under `column`.
    std::string at(const Record& record, const std::string& column) const {
      const auto found = std::find(header.begin(), header.end(), column);
      EXPECT_NE(found, header.end()) << column;
      const auto index = static_cast<std::size_t>(found - header.begin());
      return found == header.end() || index >= record.size() ? std::string("(none)") : record[index];
    }
    /// The records at `address` (a byte pair has two).
    std::vector<Record> rows_at(const std::string& address) const {
      std::vector<Record> found;
      for (const auto& record : records)
        if (at(record, "address") == address) found.push_back(record);
      return found;
    }
  };

  // RFC 4180 as the map writes it: fields with a comma, quote or newline quoted, "" for a quote.
  static Csv parse(const std::string& text) {
    std::vector<Record> lines(1);
    std::string field;
    bool quoted = false;
    for (std::size_t i = 0; i < text.size(); ++i) {
      const char c = text[i];
      if (quoted) {
        if (c == '"' && i + 1 < text.size() && text[i + 1] == '"') field += text[++i];
        else if (c == '"') quoted = false;
        else field += c;
      } else if (c == '"') {
        quoted = true;
      } else if (c == ',') {
        lines.back().push_back(std::move(field));
        field.clear();
      } else if (c == '\n') {
        lines.back().push_back(std::move(field));
        field.clear();
        lines.emplace_back();
      } else {
        field += c;
      }
    }
    if (!lines.back().empty() || !field.empty()) lines.back().push_back(std::move(field));
    else lines.pop_back();
    Csv csv{lines.front(), {lines.begin() + 1, lines.end()}};
    for (const auto& record : csv.records) EXPECT_EQ(record.size(), csv.header.size()) << record.front();
    return csv;
  }

  static CommandResult map(const std::string& options) {
    return run(bridge_cli() + " map --config " UNIMA_SOURCE_DIR "/config/examples/four-devices.yaml " + options);
  }
};

TEST_F(MapCsvForATagImport, TheHighHalfOfAPairIsWorthItsOwnScaleAndNamesItsPartner) {
  const auto [status, output] = map("--format csv");
  ASSERT_EQ(status, 0) << output;
  const auto csv = parse(output);
  EXPECT_EQ(csv.header, (Record{"address", "bank", "offset", "id", "label", "kind", "unit", "scale", "access", "source",
                                "input_register", "holding_register", "data_type", "part", "bits", "partner",
                                "word_order"}));
  const auto hours = csv.rows_at("0x1103");
  ASSERT_EQ(hours.size(), 1u);
  EXPECT_EQ(csv.at(hours[0], "id"), "operating_hours_high");
  EXPECT_EQ(csv.at(hours[0], "label"), "Motohodiny, vyšší slovo");
  EXPECT_EQ(csv.at(hours[0], "scale"), "65536");  // seconds per unit of the high word (seed: 65536s)
  EXPECT_EQ(csv.at(hours[0], "unit"), "s");
  EXPECT_EQ(csv.at(hours[0], "part"), "high");
  EXPECT_EQ(csv.at(hours[0], "partner"), "0x1102");
  EXPECT_EQ(csv.at(hours[0], "word_order"), "low_first");
  const auto low = csv.rows_at("0x1102");
  ASSERT_EQ(low.size(), 1u);
  EXPECT_EQ(csv.at(low[0], "scale"), "1");
  EXPECT_EQ(csv.at(low[0], "partner"), "0x1103");
  const auto energy = csv.rows_at("0x113B");
  ASSERT_EQ(energy.size(), 1u);
  EXPECT_EQ(csv.at(energy[0], "scale"), "6553.6");  // 65536 × 0.1 kWh
  EXPECT_EQ(csv.at(energy[0], "unit"), "kWh");
  // D4 is the UIS: a byte pair is a row per byte, each with its place, unit and scale.
  const auto knock = csv.rows_at("0x1408");
  ASSERT_EQ(knock.size(), 2u);
  EXPECT_EQ(csv.at(knock[0], "bits"), "7..0");
  EXPECT_EQ(csv.at(knock[0], "unit"), "");
  EXPECT_EQ(csv.at(knock[1], "bits"), "15..8");
  EXPECT_EQ(csv.at(knock[1], "part"), "byte_high");
  EXPECT_EQ(csv.at(knock[1], "unit"), "%");
  EXPECT_EQ(csv.at(knock[1], "scale"), "0.78125");
}

TEST_F(MapCsvForATagImport, PairsAsUint32AreOneRowEach) {
  const auto [status, output] = map("--format csv --pairs uint32");
  ASSERT_EQ(status, 0) << output;
  const auto csv = parse(output);
  const auto hours = csv.rows_at("0x1102");
  ASSERT_EQ(hours.size(), 1u);
  EXPECT_EQ(csv.at(hours[0], "id"), "operating_hours");
  EXPECT_EQ(csv.at(hours[0], "data_type"), "uint32");
  EXPECT_EQ(csv.at(hours[0], "part"), "pair");
  EXPECT_EQ(csv.at(hours[0], "partner"), "0x1103");
  EXPECT_EQ(csv.at(hours[0], "scale"), "1");
  EXPECT_TRUE(csv.rows_at("0x1103").empty());  // never the same quantity twice
  EXPECT_EQ(map("--format csv --pairs both").status, 2);
}

TEST_F(MapCsvForATagImport, TheByteOrderMarkIsForCsvOnly) {
  const auto [status, output] = map("--format csv --bom");
  ASSERT_EQ(status, 0) << output;
  EXPECT_EQ(output.substr(0, 11), "\xEF\xBB\xBF" "address,");
  const auto plain = map("--format csv");
  EXPECT_EQ(plain.output.substr(0, 8), "address,");
  for (const std::string format : {"json", "table"}) {
    const auto refused = map("--format " + format + " --bom");
    EXPECT_EQ(refused.status, 2) << format;
    EXPECT_NE(refused.output.find("--bom is for --format csv only"), std::string::npos) << refused.output;
  }
}

TEST_F(MapCsvForATagImport, ReservesAreLeftOutWhenAsked) {
  const auto is_reserve = [](const Csv& csv) {
    return std::count_if(csv.records.begin(), csv.records.end(),
                         [&](const Record& record) { return csv.at(record, "kind") == "reserve"; });
  };
  const auto with = parse(map("--format csv").output);
  const auto without = parse(map("--format csv --no-reserved").output);
  EXPECT_GT(is_reserve(with), 0);  // the default lists every served register
  EXPECT_EQ(is_reserve(without), 0);
  EXPECT_EQ(without.records.size() + static_cast<std::size_t>(is_reserve(with)), with.records.size());
}

}  // namespace
}  // namespace unima::test
