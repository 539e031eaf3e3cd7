#pragma once
// Every register a config serves, described for integrators (`unima-bridge map`): one row
// per register for the page and /api/registers; for a SCADA's tag import (MapShape) one
// row per byte of a byte pair, a 32-bit pair as one row if asked, reserves left out if
// asked. docs/man/unima-bridge.1 and docs/configuration.md list the columns.

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "config/config.hpp"

namespace unima::config {

/// Which part of its register(s) a row reads.
enum class RowPart : std::uint8_t {
  word,       // the whole register
  low,        // the low half of a 32-bit pair
  high,       // the high half of a 32-bit pair
  pair,       // both halves as one 32-bit value, from the row's address and its partner
  byte_low,   // bits 7..0 of the register
  byte_high,  // bits 15..8 of the register
};

std::string_view part_name(RowPart part);

struct MapRow {
  std::uint16_t address = 0;
  std::string bank;    // "A", "D1", "read", "write"
  std::uint16_t offset = 0;
  std::string id;      // stable English identifier
  std::string label;   // the seed's Czech label
  std::string kind;    // analog, bits, u32_low, ...
  std::string unit;
  double scale = 1.0;  // one unit of what the row reads, in `unit` (a high half: 65536 × the pair's)
  std::string access;  // "R", "W" or "RW"
  std::string source;  // what a mapped register or read block shows
  std::string data_type = "uint16";  // uint16, int16, uint32, uint8 or char (an ASCII byte)
  RowPart part = RowPart::word;
  std::optional<std::uint16_t> partner;  // the other register of a 32-bit pair, when served beside it
};

/// The pairs' word order on Modbus: the lower address holds the low word (seed §6.2.4,
/// "nižší slovo" at +0x02, "vyšší slovo" at +0x03). Empty for a row that is not a pair's.
std::string_view word_order(const MapRow& row);

/// The bits of its register a byte row reads ("15..8", "7..0"); empty for other rows.
std::string bits_of(const MapRow& row);

/// How a SCADA's tag import wants the rows (`unima-bridge map` options).
struct MapShape {
  bool bytes_apart = false;   // a row per byte of a byte or ASCII pair, each with its own label, unit, scale
  bool pairs_joined = false;  // a 32-bit pair of a device bank as one uint32 row in place of its halves
  bool reserves = true;       // the reserves of the device tables
};

/// In address order (a register's bytes in the table's order); the default shape has one
/// row per register.
std::vector<MapRow> register_map(const Config& config, MapShape shape = {});

}  // namespace unima::config
