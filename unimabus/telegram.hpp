#pragma once
// What every UnimaBUS transport delivers (SPEC §6): values of consecutive registers of one
// device (address, slot) from a register offset on. The components of one unit share an
// address (seed §3.2.1), so a telegram may also name the device type it comes from.

#include <cstdint>
#include <vector>

#include "banks/device_table.hpp"

namespace unima::unimabus {

struct Telegram {
  std::uint8_t address = 0;  // UnimaBUS device address
  std::uint8_t slot = 0;     // 0: the device itself (D_N); 1..7: IO module (S_N)
  std::uint16_t offset = 0;
  std::vector<std::uint16_t> values;
  /// The D_N device type the values come from (slot 0 only); nullptr when not named.
  const banks::DeviceTable* device = nullptr;
};

}  // namespace unima::unimabus
