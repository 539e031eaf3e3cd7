#pragma once
// Modbus constants (Modbus Application Protocol Specification V1.1b3; seed 004 §5).

#include <cstdint>

namespace unima::modbus {

namespace function {
inline constexpr std::uint8_t read_coils = 0x01;
inline constexpr std::uint8_t read_discrete_inputs = 0x02;
inline constexpr std::uint8_t read_holding_registers = 0x03;
inline constexpr std::uint8_t read_input_registers = 0x04;
inline constexpr std::uint8_t write_single_coil = 0x05;
inline constexpr std::uint8_t write_single_register = 0x06;
inline constexpr std::uint8_t write_multiple_coils = 0x0F;
inline constexpr std::uint8_t write_multiple_registers = 0x10;
inline constexpr std::uint8_t encapsulated_interface = 0x2B;
inline constexpr std::uint8_t exception_flag = 0x80;

/// Functions 1-4, which only read. Every other function counts as a write where a right
/// is asked (modbus/write_rights, the gateway's `functions: read`), the ones the bridge
/// does not know too (23, 43, a vendor's): it forwards them unread, so it cannot tell that
/// they change nothing.
constexpr bool only_reads(std::uint8_t function) { return function >= read_coils && function <= read_input_registers; }
}  // namespace function

/// Modbus exception codes; the seed's Err01..Err04 are the first four (seed 004 §5.3).
enum class ExceptionCode : std::uint8_t {
  none = 0x00,
  illegal_function = 0x01,
  illegal_data_address = 0x02,
  illegal_data_value = 0x03,
  server_device_failure = 0x04,
  server_device_busy = 0x06,
  gateway_path_unavailable = 0x0A,
  gateway_target_failed = 0x0B,
};

inline constexpr std::uint8_t mei_read_device_identification = 0x0E;

/// A PDU is at most 253 bytes (256-byte RTU ADU less address and CRC).
inline constexpr std::size_t max_pdu_size = 253;
/// Seed §5.1: a response is at most 256 bytes, so 125 registers over RTU, 123 over TCP.
inline constexpr std::uint16_t max_read_registers_rtu = 125;
inline constexpr std::uint16_t max_read_registers_tcp = 123;
inline constexpr std::uint16_t max_write_registers = 123;

/// Unit ids a TCP slave answers besides its own (SPEC §3).
inline constexpr std::uint8_t unit_id_any = 0x00;
inline constexpr std::uint8_t unit_id_not_used = 0xFF;
inline constexpr std::uint8_t broadcast_address = 0x00;

}  // namespace unima::modbus
