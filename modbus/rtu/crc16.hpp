#pragma once
// The Modbus RTU CRC-16 (polynomial 0xA001 reflected, initial 0xFFFF; Modbus over Serial
// Line V1.02 §6.2.2). On the wire the low byte goes first.

#include <cstdint>
#include <span>

namespace unima::modbus {

std::uint16_t crc16(std::span<const std::uint8_t> bytes);

}  // namespace unima::modbus
