#pragma once
// What every UnimaBUS transport delivers (SPEC §6): values of consecutive registers of one
// device (address, slot) from a register offset on.

#include <cstdint>
#include <vector>

namespace unima::unimabus {

struct Telegram {
  std::uint8_t address = 0;  // UnimaBUS device address
  std::uint8_t slot = 0;     // 0: the device itself (D_N); 1..7: IO module (S_N)
  std::uint16_t offset = 0;
  std::vector<std::uint16_t> values;
};

}  // namespace unima::unimabus
