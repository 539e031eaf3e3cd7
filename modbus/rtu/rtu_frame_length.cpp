#include "modbus/rtu/rtu_frame_length.hpp"

#include "modbus/protocol.hpp"
#include "modbus/rtu/rtu_adu.hpp"

namespace unima::modbus {

namespace {

using Kind = RtuFrameLength::Kind;

constexpr RtuFrameLength need_more{Kind::need_more, 0};
constexpr RtuFrameLength unknown{Kind::unknown, 0};
constexpr RtuFrameLength impossible{Kind::impossible, 0};
constexpr std::size_t crc_size = 2;
// Address, function, first address, count or value: requests 1–6, responses 5, 6, 15, 16.
constexpr std::size_t fixed_frame_size = 1 + 1 + 2 + 2 + crc_size;
// Before the data of a read response: address, function, byte count.
constexpr std::size_t read_response_head = 3;
// Before the data of a request 15 or 16: address, function, first, count, byte count.
constexpr std::size_t write_multiple_head = 7;

RtuFrameLength known(std::size_t bytes) {
  return bytes <= max_rtu_adu_size ? RtuFrameLength{Kind::known, bytes} : impossible;
}

bool reads_bits(std::uint8_t fn) { return fn == function::read_coils || fn == function::read_discrete_inputs; }
bool reads_registers(std::uint8_t fn) {
  return fn == function::read_holding_registers || fn == function::read_input_registers;
}
bool reads(std::uint8_t fn) { return reads_bits(fn) || reads_registers(fn); }

// Response of 43/14 (§6.21): address, 0x2B, 0x0E, read code, conformity, more follows,
// next object, object count, then per object: id, length, value.
RtuFrameLength device_identification_response(std::span<const std::uint8_t> held) {
  constexpr std::size_t objects_at = 8;
  if (held.size() < objects_at) return need_more;
  std::size_t at = objects_at;
  for (unsigned object = 0; object < held[7]; ++object) {
    if (held.size() < at + 2) return need_more;
    at += 2 + held[at + 1];
    if (at + crc_size > max_rtu_adu_size) return impossible;
  }
  return known(at + crc_size);
}

}  // namespace

RtuFrameLength rtu_request_length(std::span<const std::uint8_t> held) {
  if (held.size() < 2) return need_more;
  const std::uint8_t address = held[0];
  const std::uint8_t fn = held[1];
  if (fn == 0 || (fn & function::exception_flag)) return impossible;
  if (address == broadcast_address && reads(fn)) return impossible;
  switch (fn) {
    case function::read_coils:
    case function::read_discrete_inputs:
    case function::read_holding_registers:
    case function::read_input_registers:
    case function::write_single_coil:
    case function::write_single_register: return known(fixed_frame_size);
    case function::write_multiple_coils:
    case function::write_multiple_registers:
      if (held.size() < write_multiple_head) return need_more;
      return known(write_multiple_head + held[write_multiple_head - 1] + crc_size);
    case function::encapsulated_interface:
      if (held.size() < 3) return need_more;
      if (held[2] != mei_read_device_identification) return unknown;
      if (address == broadcast_address) return impossible;
      return known(7);  // address, function, MEI type, read code, object id, CRC
    default: return unknown;
  }
}

RtuFrameLength rtu_response_length(std::span<const std::uint8_t> held) {
  if (held.size() < 2) return need_more;
  const std::uint8_t address = held[0];
  const std::uint8_t fn = held[1];
  if (address == broadcast_address || fn == 0 || fn == function::exception_flag) return impossible;
  if (fn & function::exception_flag) return known(5);  // address, function | 0x80, code, CRC
  switch (fn) {
    case function::read_coils:
    case function::read_discrete_inputs:
    case function::read_holding_registers:
    case function::read_input_registers: {
      if (held.size() < read_response_head) return need_more;
      const std::uint8_t byte_count = held[read_response_head - 1];
      if (byte_count == 0) return impossible;
      if (reads_registers(fn) && byte_count % 2 != 0) return impossible;
      return known(read_response_head + byte_count + crc_size);
    }
    case function::write_single_coil:
    case function::write_single_register:
    case function::write_multiple_coils:
    case function::write_multiple_registers: return known(fixed_frame_size);
    case function::encapsulated_interface:
      if (held.size() < 3) return need_more;
      if (held[2] != mei_read_device_identification) return unknown;
      return device_identification_response(held);
    default: return unknown;
  }
}

std::size_t rtu_request_size(std::uint8_t function, std::uint16_t count) {
  switch (function) {
    case function::write_multiple_registers: return write_multiple_head + 2u * count + crc_size;
    case function::write_multiple_coils: return write_multiple_head + (count + 7u) / 8u + crc_size;
    default: return fixed_frame_size;
  }
}

std::size_t rtu_response_size(std::uint8_t function, std::uint16_t count) {
  if (reads_bits(function)) return read_response_head + (count + 7u) / 8u + crc_size;
  if (reads_registers(function)) return read_response_head + 2u * count + crc_size;
  return fixed_frame_size;
}

}  // namespace unima::modbus
