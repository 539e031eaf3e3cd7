#pragma once
// The Modbus RTU ADU: address, PDU, CRC-16 low byte first (Modbus over Serial Line V1.02
// §2.3.1, §6.2.2).

#include <cstdint>
#include <span>

namespace unima::modbus {

inline constexpr std::size_t max_rtu_adu_size = 256;
/// Address, function and CRC: nothing shorter can be a frame.
inline constexpr std::size_t min_rtu_adu_size = 4;

/// True when `adu` is long enough and its last two bytes are the CRC of the others.
bool rtu_crc_ok(std::span<const std::uint8_t> adu);

/// Writes address + pdu + CRC into `out` (at least pdu.size() + 3 bytes); returns the size.
std::size_t write_rtu_adu(std::uint8_t address, std::span<const std::uint8_t> pdu, std::span<std::uint8_t> out);

}  // namespace unima::modbus
