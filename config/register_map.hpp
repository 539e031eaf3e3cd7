#pragma once
// Every register a config serves, described for integrators (`unima-bridge map`).

#include <cstdint>
#include <string>
#include <vector>

#include "config/config.hpp"

namespace unima::config {

struct MapRow {
  std::uint16_t address = 0;
  std::string bank;    // "A", "D1", "read", "write"
  std::uint16_t offset = 0;
  std::string id;      // stable English identifier
  std::string label;   // the seed's Czech label
  std::string kind;    // analog, bits, u32_low, ...
  std::string unit;
  double scale = 1.0;
  std::string access;  // "R", "W" or "RW"
  std::string source;  // what a mapped register or read block shows
};

/// In address order.
std::vector<MapRow> register_map(const Config& config);

}  // namespace unima::config
