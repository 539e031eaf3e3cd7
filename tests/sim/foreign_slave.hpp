#pragma once
// A foreign Modbus slave as its seed describes it (SPEC §9), for the simulator: the data
// tables of its device profile, answering request PDUs the way the device does — functions
// it lacks get exception 01, addresses outside its map exception 02, malformed requests
// exception 03. Pure.

#include <cstdint>
#include <map>
#include <optional>
#include <span>
#include <vector>

#include "master/device_profile.hpp"

namespace unima::sim {

using Bytes = std::vector<std::uint8_t>;

class ForeignSlave {
 public:
  /// Registers and coils from the profile's points, holding the values the seed quotes.
  explicit ForeignSlave(const master::DeviceProfile& profile);

  /// The response PDU to `request` (a request PDU: function and data).
  Bytes answer(std::span<const std::uint8_t> request);

  const master::DeviceProfile& profile() const { return *profile_; }
  /// A holding register (what functions 3, 6, 16 reach); nullopt outside the map.
  std::optional<std::uint16_t> holding(std::uint16_t reg) const;
  bool set_holding(std::uint16_t reg, std::uint16_t value);
  /// A discrete input (function 2); false outside the map.
  bool set_input(std::uint16_t reg, bool on);
  /// A coil (functions 1, 5, 15); nullopt outside the map.
  std::optional<bool> coil(std::uint16_t reg) const;

 private:
  struct Cell {
    std::uint16_t value = 0;
    bool readable = false;
    bool writable = false;
  };
  using Table = std::map<std::uint16_t, Cell>;

  Table& table(master::DataTable t) { return tables_[static_cast<std::size_t>(t)]; }
  const Table& table(master::DataTable t) const { return tables_[static_cast<std::size_t>(t)]; }
  Bytes read(std::uint8_t function, std::span<const std::uint8_t> request);
  Bytes write(std::uint8_t function, std::span<const std::uint8_t> request);

  const master::DeviceProfile* profile_;
  std::array<Table, 4> tables_;
};

}  // namespace unima::sim
