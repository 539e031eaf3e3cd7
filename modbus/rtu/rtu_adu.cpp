#include "modbus/rtu/rtu_adu.hpp"

#include <algorithm>

#include "modbus/rtu/crc16.hpp"

namespace unima::modbus {

bool rtu_crc_ok(std::span<const std::uint8_t> adu) {
  if (adu.size() < min_rtu_adu_size) return false;
  const auto crc = crc16(adu.first(adu.size() - 2));
  return adu[adu.size() - 2] == (crc & 0xFF) && adu[adu.size() - 1] == (crc >> 8);
}

std::size_t write_rtu_adu(std::uint8_t address, std::span<const std::uint8_t> pdu, std::span<std::uint8_t> out) {
  out[0] = address;
  std::copy(pdu.begin(), pdu.end(), out.begin() + 1);
  const std::size_t body = pdu.size() + 1;
  const auto crc = crc16(out.first(body));
  out[body] = static_cast<std::uint8_t>(crc & 0xFF);
  out[body + 1] = static_cast<std::uint8_t>(crc >> 8);
  return body + 2;
}

}  // namespace unima::modbus
