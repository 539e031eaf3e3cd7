#pragma once
// `unima-bridge map` output: the register map as an aligned table, CSV or JSON.

#include <string>
#include <vector>

#include "config/register_map.hpp"

namespace unima::cli {

enum class MapFormat { table, csv, json };

std::string format_register_map(const std::vector<config::MapRow>& rows, MapFormat format);

}  // namespace unima::cli
