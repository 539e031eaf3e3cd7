#pragma once
// The master's side of the Modbus protocol: request PDUs and frames, and the check of a
// response against its request (Modbus Application Protocol V1.1b3 §6; seed 004 §8 for the
// error states). Pure: the RTU and TCP links feed it bytes.

#include <cstdint>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "master/master_plan.hpp"
#include "modbus/protocol.hpp"
#include "modbus/transaction.hpp"

namespace unima::master {

using Bytes = std::vector<std::uint8_t>;

/// Request PDU of a read (functions 1–4): function, first, count.
Bytes read_request_pdu(std::uint8_t function, std::uint16_t first, std::uint16_t count);
/// Request PDU of a write. Function 5 writes values[0] != 0 as 0xFF00 (on), else 0x0000;
/// function 6 values[0]; function 15 one coil per value; function 16 every value.
Bytes write_request_pdu(std::uint8_t function, std::uint16_t first, std::span<const std::uint16_t> values);
/// An RTU frame: address, PDU, CRC (low byte first).
Bytes rtu_frame(std::uint8_t address, std::span<const std::uint8_t> pdu);

/// What became of a request.
enum class ResponseStatus : std::uint8_t {
  ok,
  exception,       // a Modbus exception response; see MasterResponse::exception
  timeout,         // nothing heard
  bad_crc,         // RTU CRC wrong
  bad_length,      // byte count does not fit the request
  too_short,       // fewer than 5 bytes (RTU) or an incomplete ADU
  wrong_function,  // function code neither the request's nor its exception
  wrong_address,   // from another slave or unit
  wrong_echo,      // a write's response does not repeat the request
  bad_frame,       // TCP: an MBAP header that cannot be (protocol id, length)
};

std::string_view response_status_name(ResponseStatus status);

struct MasterResponse {
  ResponseStatus status = ResponseStatus::timeout;
  modbus::ExceptionCode exception = modbus::ExceptionCode::none;
  std::span<const std::uint8_t> pdu;  // function and data, when status is ok or exception
};

/// The monitor state of an outcome (SPEC §5): Done, Err01..Err04 for exceptions, Err03 for
/// a bad CRC or length, Err04 for a short frame, a wrong function (seed §8) or another
/// slave's or a wrong echo, Timeout when nothing came.
modbus::TransactionState transaction_state(const MasterResponse& response);
/// A merged read answered with exception 02 reaches a register the slave does not have:
/// its blocks are read apart from then on (docs/master.md). The requests that replace
/// `request`, or none when the rule does not apply.
std::vector<PlannedRequest> split_after(const PlannedRequest& request, const MasterResponse& response,
                                        std::span<const MasterBlock> blocks);

/// Whether the slave is alive by this response: it answered something it meant for us
/// (a gateway's exception 0x0A or 0x0B says the slave behind it did not).
bool slave_answered(const MasterResponse& response);

/// The length an RTU response to a request of `request_function` will have, once enough
/// of it is there to tell (modbus::rtu_response_length); nullopt while unknown, and for a
/// reply of another function: then only silence ends the frame.
std::optional<std::size_t> expected_response_length(std::span<const std::uint8_t> bytes, std::uint8_t request_function);

/// Checks an RTU response frame (as ended by its length or by silence) against the request.
MasterResponse check_rtu_response(std::span<const std::uint8_t> frame, std::uint8_t address,
                                  std::span<const std::uint8_t> request_pdu);
/// Checks the answer to a forwarded request (SPEC §14) against the request, as a poll's
/// is: its frame (length, CRC, address), then its function or its exception; for the
/// functions the master knows (1–6, 15, 16) as check_response_pdu does — for 1–4 a byte
/// count that fits the quantity asked, for 5, 6, 15 and 16 the echo. Another function's
/// answer is taken as it came. ok or exception with `pdu` the slave's answer PDU; else
/// timeout, too_short, bad_crc, wrong_address, wrong_function, bad_length or wrong_echo:
/// a late answer to an earlier request is never handed to this one's client.
MasterResponse check_forwarded_rtu_answer(std::span<const std::uint8_t> frame, std::uint8_t address,
                                          std::span<const std::uint8_t> request_pdu);
/// Checks a TCP response ADU (MBAP + PDU) against the request's unit and PDU. The
/// transaction id is matched by the link, which skips late answers to older requests.
MasterResponse check_tcp_response(std::span<const std::uint8_t> adu, std::uint8_t unit,
                                  std::span<const std::uint8_t> request_pdu);
/// Checks a response PDU against the request PDU.
MasterResponse check_response_pdu(std::span<const std::uint8_t> pdu, std::span<const std::uint8_t> request_pdu);

/// The values of a checked read response: registers, or one 0/1 per coil or input.
std::vector<std::uint16_t> response_values(std::span<const std::uint8_t> pdu, std::uint8_t function,
                                           std::uint16_t count);

/// A poll block's bridge register from the values of its request (which starts at
/// `request_first`): bits packed, bit n = coil reg + n; registers decoded and scaled.
std::uint16_t poll_output(const MasterBlock& block, std::uint16_t request_first, std::span<const std::uint16_t> values);
/// The values a send block writes for the bridge register `raw`.
std::vector<std::uint16_t> send_values(const MasterBlock& block, std::uint16_t raw);

}  // namespace unima::master
