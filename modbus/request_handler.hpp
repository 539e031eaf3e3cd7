#pragma once
// Answers one request PDU with one response PDU (seed 004 §5, SPEC §3). Pure: the TCP
// and RTU adapters frame the PDUs; this decides function, exceptions and data.

#include <cstdint>
#include <span>
#include <string>

#include "modbus/protocol.hpp"
#include "modbus/register_model.hpp"
#include "modbus/write_rights.hpp"

namespace unima::modbus {

/// Objects of function 43/14 (Read Device Identification), basic and regular categories.
struct DeviceIdentity {
  std::string vendor_name = "unima-bridge";
  std::string product_code = "UNIMA-BRIDGE";
  std::string revision = "0.1.0";
  std::string vendor_url;
  std::string product_name = "Unima Bridge UnimaBUS/Modbus gateway";
  std::string model_name;
  std::string user_application_name;
};

struct HandlerOptions {
  std::uint16_t max_read_registers = max_read_registers_tcp;
  /// Extensions beyond the seed's functions 4 and 6 (SPEC §3), each switchable off.
  bool read_holding_registers = true;    // 3, answered like 4
  bool write_multiple_registers = true;  // 16
  bool device_identification = true;     // 43/14
  DeviceIdentity identity;
};

/// A response PDU written, and what a write in it kept (WriteResult::kept_as).
struct Handled {
  std::size_t length = 0;
  std::uint64_t kept_as = 0;
};

/// Writes the response to `request` into `response` (at least max_pdu_size bytes). A
/// request PDU must hold at least the function code. A well-formed write to a register
/// outside `rights` (nullptr: every register) is exception 01, one outside the writable
/// registers 02 (`registers` decides both, banks::WritePath for the bridge).
Handled handle_request(std::span<const std::uint8_t> request, std::span<std::uint8_t> response,
                           RegisterModel& registers, const HandlerOptions& options,
                           const WriteRights* rights = nullptr);

/// An exception response PDU: function | 0x80, code. Returns 2.
std::size_t write_exception(std::uint8_t function, ExceptionCode code, std::span<std::uint8_t> response);

/// The answer to a write of function `function` that was taken and then refused (`why`:
/// WriteResult::Status::not_kept, the state file could not keep it), in place of the
/// answer handle_request wrote: the exception that status means. Returns its length.
std::size_t answer_refused_write(std::uint8_t function, WriteResult::Status why, std::span<std::uint8_t> response);

/// The exception code of a response PDU, or ExceptionCode::none for a normal response.
ExceptionCode exception_of(std::span<const std::uint8_t> response);

}  // namespace unima::modbus
