#pragma once
// `unima-bridge map` output: the register map as a table for an 80..100-column terminal,
// CSV or JSON (every field), each row with the PLC-style numbers (modbus/plc_numbers) a
// SCADA integrator types: the input register (function 4) and the holding register
// (function 3 reads, 6 and 16 write) the address is served as.

#include <string>
#include <vector>

#include "config/register_map.hpp"

namespace unima::cli {

enum class MapFormat { table, csv, json };

/// How the config serves a register besides function 4 (SPEC §3).
struct ServedFunctions {
  bool function_3 = true;  // reads of holding registers, answered like function 4
};

/// The widest line of the table, in characters: long labels are cut to fit (csv and json have them whole).
inline constexpr std::size_t map_table_width = 100;

std::string format_register_map(const std::vector<config::MapRow>& rows, MapFormat format, ServedFunctions served);

}  // namespace unima::cli
