#include "config/register_map_json.hpp"

#include <fmt/format.h>

namespace unima::config {

nlohmann::json map_row_json(const MapRow& row) {
  return {{"address", fmt::format("0x{:04X}", row.address)},
          {"bank", row.bank},
          {"offset", row.offset},
          {"id", row.id},
          {"label", row.label},
          {"kind", row.kind},
          {"unit", row.unit},
          {"scale", row.scale},
          {"access", row.access},
          {"source", row.source}};
}

}  // namespace unima::config
