// `unima-bridge map` for a SCADA's tag import (issue 44, finding 5): rows built from the
// real device tables, in csv and json — a 32-bit pair's halves each worth what one unit of
// that register is worth, with the partner and the word order, or the pair as one uint32
// row; a byte pair as a row per byte; reserves left out when asked; the byte order mark.

#include <gtest/gtest.h>

#include <algorithm>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli/register_map_format.hpp"
#include "config/register_map.hpp"

namespace unima {
namespace {

using config::MapRow;
using config::RowPart;

// D1 at 0x1100 (operating hours +0x02/+0x03, energy +0x3A/+0x3B), D2 at 0x1200 (UIS:
// knock ranks +0x08.., a reserve at +0x0B).
const config::Config& chp_and_uis() {
  static const auto config = config::load_text(
      "devices:\n"
      "  D1: { type: unigen-chp, address: 5 }\n"
      "  D2: { type: uis, address: 6 }\n",
      "t.yaml");
  return config;
}

constexpr config::MapShape for_import{.bytes_apart = true};

std::vector<MapRow> rows_at(const std::vector<MapRow>& rows, std::uint16_t address) {
  std::vector<MapRow> found;
  std::copy_if(rows.begin(), rows.end(), std::back_inserter(found), [&](const MapRow& r) { return r.address == address; });
  return found;
}

MapRow row_at(const std::vector<MapRow>& rows, std::uint16_t address) {
  const auto found = rows_at(rows, address);
  EXPECT_EQ(found.size(), 1u) << "rows at " << address;
  return found.empty() ? MapRow{} : found.front();
}

// The csv line of `text` that starts with `start`.
std::string csv_line(const std::string& text, const std::string& start) {
  const auto at = text.find("\n" + start);
  if (at == std::string::npos) return {};
  return text.substr(at + 1, text.find('\n', at + 1) - at - 1);
}

TEST(MapForImport, EachHalfOfA32BitPairIsWorthWhatOneUnitOfItsRegisterIs) {
  const auto rows = config::register_map(chp_and_uis(), for_import);
  const auto low = row_at(rows, 0x1102), high = row_at(rows, 0x1103);
  EXPECT_EQ(low.id, "operating_hours_low");
  EXPECT_EQ(low.part, RowPart::low);
  EXPECT_EQ(low.partner, std::optional<std::uint16_t>(0x1103));
  EXPECT_DOUBLE_EQ(low.scale, 1.0);
  EXPECT_EQ(low.unit, "s");
  EXPECT_EQ(high.id, "operating_hours_high");
  EXPECT_EQ(high.part, RowPart::high);
  EXPECT_EQ(high.partner, std::optional<std::uint16_t>(0x1102));
  EXPECT_DOUBLE_EQ(high.scale, 65536.0);  // the seed's "65536s"
  EXPECT_EQ(high.unit, "s");
  EXPECT_EQ(high.data_type, "uint16");
  EXPECT_EQ(config::word_order(high), "low_first");
  const auto energy_high = row_at(rows, 0x113B);
  EXPECT_DOUBLE_EQ(energy_high.scale, 6553.6);  // 65536 × 0.1 kWh
  EXPECT_EQ(energy_high.unit, "kWh");
  EXPECT_EQ(config::word_order(row_at(rows, 0x1101)), "");  // engine speed: no pair
  EXPECT_EQ(row_at(rows, 0x1101).partner, std::nullopt);
}

TEST(MapForImport, APairJoinedIsOneUint32RowAndItsHalvesAreNotListed) {
  auto shape = for_import;
  shape.pairs_joined = true;
  const auto rows = config::register_map(chp_and_uis(), shape);
  const auto pair = row_at(rows, 0x1102);
  EXPECT_EQ(pair.id, "operating_hours");
  EXPECT_EQ(pair.label, "Motohodiny");
  EXPECT_EQ(pair.data_type, "uint32");
  EXPECT_EQ(pair.part, RowPart::pair);
  EXPECT_EQ(pair.partner, std::optional<std::uint16_t>(0x1103));
  EXPECT_DOUBLE_EQ(pair.scale, 1.0);
  EXPECT_TRUE(rows_at(rows, 0x1103).empty());
  EXPECT_DOUBLE_EQ(row_at(rows, 0x113A).scale, 0.1);
  EXPECT_TRUE(rows_at(rows, 0x113B).empty());
  EXPECT_EQ(row_at(rows, 0x1104).id, "mains_active_power");  // the rows go on after the pair
}

TEST(MapForImport, ABytePairIsARowPerByteWithItsOwnPlaceUnitAndScale) {
  const auto bytes = rows_at(config::register_map(chp_and_uis(), for_import), 0x1208);
  ASSERT_EQ(bytes.size(), 2u);
  EXPECT_EQ(bytes[0].id, "knock_rank_1_cylinder");
  EXPECT_EQ(bytes[0].part, RowPart::byte_low);
  EXPECT_EQ(config::bits_of(bytes[0]), "7..0");
  EXPECT_EQ(bytes[0].unit, "");
  EXPECT_DOUBLE_EQ(bytes[0].scale, 1.0);
  EXPECT_EQ(bytes[0].data_type, "uint8");
  EXPECT_EQ(bytes[1].id, "knock_rank_1_level");
  EXPECT_EQ(bytes[1].part, RowPart::byte_high);
  EXPECT_EQ(config::bits_of(bytes[1]), "15..8");
  EXPECT_EQ(bytes[1].unit, "%");
  EXPECT_DOUBLE_EQ(bytes[1].scale, 0.78125);
  // The page and /api/registers keep one row per register.
  EXPECT_EQ(rows_at(config::register_map(chp_and_uis()), 0x1208).size(), 1u);
}

TEST(MapForImport, ReservesAreListedUnlessLeftOut) {
  const auto is_reserve = [](const MapRow& r) { return r.kind == "reserve"; };
  const auto with = config::register_map(chp_and_uis(), for_import);
  EXPECT_EQ(row_at(with, 0x120B).id, "reserve_0b");
  auto shape = for_import;
  shape.reserves = false;
  const auto without = config::register_map(chp_and_uis(), shape);
  EXPECT_TRUE(rows_at(without, 0x120B).empty());
  EXPECT_EQ(std::count_if(without.begin(), without.end(), is_reserve), 0);
  EXPECT_EQ(without.size() + static_cast<std::size_t>(std::count_if(with.begin(), with.end(), is_reserve)), with.size());
}

TEST(MapForImport, CsvCarriesTheNewColumnsAfterTheOldOnes) {
  const auto csv = cli::format_register_map(config::register_map(chp_and_uis(), for_import), {cli::MapFormat::csv}, {});
  EXPECT_EQ(csv.substr(0, csv.find('\n')),
            "address,bank,offset,id,label,kind,unit,scale,access,source,input_register,holding_register,data_type,part,"
            "bits,partner,word_order");
  EXPECT_EQ(csv_line(csv, "0x1103"),
            "0x1103,D1,0x03,operating_hours_high,\"Motohodiny, vyšší slovo\",u32_high,s,65536,R,,304356,404356,uint16,"
            "high,,0x1102,low_first");
  EXPECT_EQ(csv_line(csv, "0x113B").find("0x113B,D1,0x3B,generator_energy_high,"), 0u);
  EXPECT_NE(csv_line(csv, "0x113B").find(",kWh,6553.6,R,"), std::string::npos) << csv_line(csv, "0x113B");
  EXPECT_NE(csv.find("\n0x1208,D2,0x08,knock_rank_1_level,První nejvyšší úroveň detonací,byte_pair,%,0.78125,R,,"
                     "304617,404617,uint8,byte_high,15..8,,\n"),
            std::string::npos);
  EXPECT_EQ(csv.substr(0, 3), "add");  // no byte order mark unless asked
}

TEST(MapForImport, TheByteOrderMarkStartsTheCsv) {
  const auto csv =
      cli::format_register_map(config::register_map(chp_and_uis(), for_import), {cli::MapFormat::csv, true}, {});
  ASSERT_GE(csv.size(), 3u);
  EXPECT_EQ(static_cast<unsigned char>(csv[0]), 0xEF);
  EXPECT_EQ(static_cast<unsigned char>(csv[1]), 0xBB);
  EXPECT_EQ(static_cast<unsigned char>(csv[2]), 0xBF);
  EXPECT_EQ(csv.substr(3, 8), "address,");
}

TEST(MapForImport, JsonCarriesTheSameFields) {
  const auto json = nlohmann::json::parse(
      cli::format_register_map(config::register_map(chp_and_uis(), for_import), {cli::MapFormat::json}, {}));
  const auto at = [&](const std::string& address, const std::string& part) {
    const auto found = std::find_if(json.begin(), json.end(),
                                    [&](const auto& row) { return row["address"] == address && row["part"] == part; });
    return found == json.end() ? nlohmann::json() : *found;
  };
  const auto high = at("0x1103", "high");
  ASSERT_TRUE(high.is_object()) << json.dump(1);
  EXPECT_EQ(high["scale"], 65536.0);
  EXPECT_EQ(high["partner"], "0x1102");
  EXPECT_EQ(high["word_order"], "low_first");
  EXPECT_EQ(high["data_type"], "uint16");
  EXPECT_TRUE(high["bits"].is_null());
  const auto level = at("0x1208", "byte_high");
  ASSERT_TRUE(level.is_object());
  EXPECT_EQ(level["bits"], "15..8");
  EXPECT_EQ(level["unit"], "%");
  EXPECT_EQ(level["data_type"], "uint8");
  EXPECT_TRUE(level["partner"].is_null());
  EXPECT_TRUE(level["word_order"].is_null());
}

TEST(MapForImport, AHighHalfCopiedIntoBankAKeepsItsWorth) {
  const auto config = config::load_text(
      "devices: { D1: { type: unigen-chp, address: 5 } }\n"
      "mapping: { A: [ D1+0x03, D1.oil_temperature ] }\n",
      "t.yaml");
  const auto rows = config::register_map(config, for_import);
  const auto copy = row_at(rows, 0x1000);
  EXPECT_DOUBLE_EQ(copy.scale, 65536.0);
  EXPECT_EQ(copy.part, RowPart::high);
  EXPECT_EQ(copy.partner, std::nullopt);  // A+0x01 is not its other half
  const auto tenths = row_at(rows, 0x1001);
  EXPECT_EQ(tenths.data_type, "int16");  // A holds it in signed tenths
  EXPECT_DOUBLE_EQ(tenths.scale, 0.1);
}

}  // namespace
}  // namespace unima
