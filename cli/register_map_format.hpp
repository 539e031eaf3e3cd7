#pragma once
// `unima-bridge map` output: the register map as a table for an 80..100-column terminal,
// CSV or JSON (every field), each row with the PLC-style numbers (modbus/plc_numbers) a
// SCADA integrator types: the input register (function 4) and the holding register
// (function 3 reads, 6 and 16 write) the address is served as.

#include <string>
#include <string_view>
#include <vector>

#include "config/register_map.hpp"

namespace unima::cli {

enum class MapFormat { table, csv, json };

/// The output's form: the format and, for csv only (the command line refuses it
/// otherwise), the UTF-8 byte order mark Excel needs to read the Czech labels as UTF-8.
struct MapOutput {
  MapFormat format = MapFormat::table;
  bool byte_order_mark = false;
};

/// EF BB BF, the first bytes of a csv with a byte order mark.
inline constexpr std::string_view utf8_byte_order_mark = "\xEF\xBB\xBF";

/// How the config serves a register besides function 4 (SPEC §3).
struct ServedFunctions {
  bool function_3 = true;  // reads of holding registers, answered like function 4
};

/// The widest line of the table, in characters: long labels are cut to fit (csv and json have them whole).
inline constexpr std::size_t map_table_width = 100;

std::string format_register_map(const std::vector<config::MapRow>& rows, MapOutput output, ServedFunctions served);

}  // namespace unima::cli
