#pragma once
// Modbus puts every 16-bit field on the wire high byte first (Modbus Application
// Protocol V1.1b3 §4.2); the CRC of an RTU frame is the one exception (modbus/rtu/rtu_adu).

#include <cstddef>
#include <cstdint>
#include <span>

namespace unima::modbus {

inline std::uint16_t be16(std::span<const std::uint8_t> bytes, std::size_t at) {
  return static_cast<std::uint16_t>(bytes[at] << 8 | bytes[at + 1]);
}

inline void put_be16(std::span<std::uint8_t> bytes, std::size_t at, std::uint16_t value) {
  bytes[at] = static_cast<std::uint8_t>(value >> 8);
  bytes[at + 1] = static_cast<std::uint8_t>(value);
}

}  // namespace unima::modbus
