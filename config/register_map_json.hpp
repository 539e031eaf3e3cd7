#pragma once
// The register map as JSON (`unima-bridge map --format json`, and /api/registers with the
// current values): one object per register, in address order.

#include <vector>

#include <nlohmann/json.hpp>

#include "config/register_map.hpp"

namespace unima::config {

nlohmann::json map_row_json(const MapRow& row);

}  // namespace unima::config
