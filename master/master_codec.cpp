#include "master/master_codec.hpp"

#include <algorithm>

#include "modbus/rtu/crc16.hpp"
#include "modbus/rtu/rtu_adu.hpp"
#include "modbus/rtu/rtu_frame_length.hpp"
#include "modbus/mbap.hpp"
#include "modbus/bytes.hpp"

namespace unima::master {

namespace {

void put16(Bytes& out, std::uint16_t value) {
  out.push_back(static_cast<std::uint8_t>(value >> 8));
  out.push_back(static_cast<std::uint8_t>(value & 0xFF));
}

bool reads_bits(std::uint8_t fn) { return fn == modbus::function::read_coils || fn == modbus::function::read_discrete_inputs; }
bool reads_registers(std::uint8_t fn) {
  return fn == modbus::function::read_holding_registers || fn == modbus::function::read_input_registers;
}

// 5, 6, 15 and 16: the answer repeats the request's address and value or count.
bool writes_and_echoes(std::uint8_t fn) {
  return fn == modbus::function::write_single_coil || fn == modbus::function::write_single_register ||
         fn == modbus::function::write_multiple_coils || fn == modbus::function::write_multiple_registers;
}

MasterResponse status_only(ResponseStatus status) {
  MasterResponse r;
  r.status = status;
  return r;
}

}  // namespace

Bytes read_request_pdu(std::uint8_t fn, std::uint16_t first, std::uint16_t count) {
  Bytes pdu{fn};
  put16(pdu, first);
  put16(pdu, count);
  return pdu;
}

Bytes write_request_pdu(std::uint8_t fn, std::uint16_t first, std::span<const std::uint16_t> values) {
  Bytes pdu{fn};
  put16(pdu, first);
  switch (fn) {
    case modbus::function::write_single_coil: put16(pdu, values[0] != 0 ? 0xFF00 : 0x0000); break;
    case modbus::function::write_single_register: put16(pdu, values[0]); break;
    case modbus::function::write_multiple_coils: {
      put16(pdu, static_cast<std::uint16_t>(values.size()));
      const auto bytes = (values.size() + 7) / 8;
      pdu.push_back(static_cast<std::uint8_t>(bytes));
      const auto at = pdu.size();
      pdu.resize(at + bytes, 0);
      for (std::size_t i = 0; i < values.size(); ++i)
        if (values[i]) pdu[at + i / 8] = static_cast<std::uint8_t>(pdu[at + i / 8] | (1u << (i % 8)));
      break;
    }
    default:  // write multiple registers
      put16(pdu, static_cast<std::uint16_t>(values.size()));
      pdu.push_back(static_cast<std::uint8_t>(values.size() * 2));
      for (auto v : values) put16(pdu, v);
  }
  return pdu;
}

Bytes rtu_frame(std::uint8_t address, std::span<const std::uint8_t> pdu) {
  Bytes frame(pdu.size() + 3);
  modbus::write_rtu_adu(address, pdu, frame);
  return frame;
}

std::string_view response_status_name(ResponseStatus status) {
  switch (status) {
    case ResponseStatus::ok: return "ok";
    case ResponseStatus::exception: return "exception";
    case ResponseStatus::timeout: return "no answer";
    case ResponseStatus::bad_crc: return "bad CRC";
    case ResponseStatus::bad_length: return "bad length";
    case ResponseStatus::too_short: return "too short";
    case ResponseStatus::wrong_function: return "wrong function";
    case ResponseStatus::wrong_address: return "wrong address";
    case ResponseStatus::wrong_echo: return "wrong echo";
    case ResponseStatus::bad_frame: return "bad frame";
  }
  return "?";
}

modbus::TransactionState transaction_state(const MasterResponse& r) {
  switch (r.status) {
    case ResponseStatus::ok: return modbus::TransactionState::done;
    case ResponseStatus::exception:
      switch (r.exception) {
        case modbus::ExceptionCode::illegal_function: return modbus::TransactionState::err01;
        case modbus::ExceptionCode::illegal_data_address: return modbus::TransactionState::err02;
        case modbus::ExceptionCode::illegal_data_value: return modbus::TransactionState::err03;
        default: return modbus::TransactionState::err04;
      }
    case ResponseStatus::timeout: return modbus::TransactionState::timeout;
    case ResponseStatus::bad_crc:
    case ResponseStatus::bad_length: return modbus::TransactionState::err03;
    default: return modbus::TransactionState::err04;
  }
}

bool slave_answered(const MasterResponse& r) {
  if (r.status == ResponseStatus::exception) {
    // 0x0A and 0x0B come from a gateway in front of the slave: the slave itself is silent.
    return r.exception != modbus::ExceptionCode::gateway_path_unavailable && r.exception != modbus::ExceptionCode::gateway_target_failed;
  }
  return r.status == ResponseStatus::ok || r.status == ResponseStatus::bad_length || r.status == ResponseStatus::wrong_echo;
}

std::optional<std::size_t> expected_response_length(std::span<const std::uint8_t> bytes, std::uint8_t request_function) {
  if (bytes.size() < 2) return std::nullopt;
  // A reply of another function would be framed by rules that are not the answer's.
  if ((bytes[1] & ~modbus::function::exception_flag) != request_function) return std::nullopt;
  const auto length = modbus::rtu_response_length(bytes);
  if (length.kind != modbus::RtuFrameLength::Kind::known) return std::nullopt;
  return length.bytes;
}

std::vector<PlannedRequest> split_after(const PlannedRequest& request, const MasterResponse& response,
                                        std::span<const MasterBlock> blocks) {
  if (response.status != ResponseStatus::exception || response.exception != modbus::ExceptionCode::illegal_data_address ||
      !request.is_read() || request.blocks.size() < 2)
    return {};
  return split_request(request, blocks);
}

MasterResponse check_response_pdu(std::span<const std::uint8_t> pdu, std::span<const std::uint8_t> request_pdu) {
  if (pdu.empty()) return status_only(ResponseStatus::too_short);
  const auto fn = request_pdu[0];
  if (pdu[0] == (fn | modbus::function::exception_flag)) {
    if (pdu.size() != 2) return status_only(ResponseStatus::bad_length);
    MasterResponse r{ResponseStatus::exception, static_cast<modbus::ExceptionCode>(pdu[1]), pdu};
    return r;
  }
  if (pdu[0] != fn) return status_only(ResponseStatus::wrong_function);
  if (reads_bits(fn) || reads_registers(fn)) {
    const auto count = modbus::be16(request_pdu, 3);
    const std::size_t expected = reads_bits(fn) ? (count + 7u) / 8u : 2u * count;
    if (pdu.size() < 2 || pdu[1] != expected || pdu.size() != 2 + expected)
      return status_only(ResponseStatus::bad_length);
  } else {
    // 5 and 6 echo the request; 15 and 16 repeat its address and count.
    if (pdu.size() != 5) return status_only(ResponseStatus::bad_length);
    if (!std::equal(pdu.begin() + 1, pdu.end(), request_pdu.begin() + 1)) return status_only(ResponseStatus::wrong_echo);
  }
  return MasterResponse{ResponseStatus::ok, modbus::ExceptionCode::none, pdu};
}

MasterResponse check_rtu_response(std::span<const std::uint8_t> frame, std::uint8_t address,
                                  std::span<const std::uint8_t> request_pdu) {
  if (frame.empty()) return status_only(ResponseStatus::timeout);
  if (frame.size() < 5) return status_only(ResponseStatus::too_short);
  const auto body = frame.first(frame.size() - 2);
  const auto crc = static_cast<std::uint16_t>(frame[frame.size() - 2] | frame[frame.size() - 1] << 8);
  if (modbus::crc16(body) != crc) return status_only(ResponseStatus::bad_crc);
  if (frame[0] != address) return status_only(ResponseStatus::wrong_address);
  return check_response_pdu(body.subspan(1), request_pdu);
}

MasterResponse check_forwarded_rtu_answer(std::span<const std::uint8_t> frame, std::uint8_t address,
                                          std::span<const std::uint8_t> request_pdu) {
  if (frame.empty()) return status_only(ResponseStatus::timeout);
  if (frame.size() < 4) return status_only(ResponseStatus::too_short);
  const auto body = frame.first(frame.size() - 2);
  const auto crc = static_cast<std::uint16_t>(frame[frame.size() - 2] | frame[frame.size() - 1] << 8);
  if (modbus::crc16(body) != crc) return status_only(ResponseStatus::bad_crc);
  if (frame[0] != address) return status_only(ResponseStatus::wrong_address);
  const auto pdu = body.subspan(1);
  if (pdu.size() > modbus::max_pdu_size) return status_only(ResponseStatus::bad_length);
  const auto fn = request_pdu[0];
  if (pdu[0] == (fn | modbus::function::exception_flag)) {
    if (pdu.size() != 2) return status_only(ResponseStatus::bad_length);
    return MasterResponse{ResponseStatus::exception, static_cast<modbus::ExceptionCode>(pdu[1]), pdu};
  }
  if (pdu[0] != fn) return status_only(ResponseStatus::wrong_function);
  if (!reads_bits(fn) && !reads_registers(fn) && !writes_and_echoes(fn))
    return MasterResponse{ResponseStatus::ok, modbus::ExceptionCode::none, pdu};
  // Data to a request too short to say its address and quantity answers no such request.
  if (request_pdu.size() < 5) return status_only(ResponseStatus::bad_frame);
  return check_response_pdu(pdu, request_pdu);
}

MasterResponse check_tcp_response(std::span<const std::uint8_t> adu, std::uint8_t unit,
                                  std::span<const std::uint8_t> request_pdu) {
  if (adu.empty()) return status_only(ResponseStatus::timeout);
  const auto parsed = modbus::parse_tcp_adu(adu);
  if (parsed.status == modbus::TcpAdu::Status::bad_header) return status_only(ResponseStatus::bad_frame);
  if (parsed.status == modbus::TcpAdu::Status::need_more) return status_only(ResponseStatus::too_short);
  if (parsed.header.unit_id != unit) return status_only(ResponseStatus::wrong_address);
  return check_response_pdu(parsed.pdu, request_pdu);
}

std::vector<std::uint16_t> response_values(std::span<const std::uint8_t> pdu, std::uint8_t fn, std::uint16_t count) {
  std::vector<std::uint16_t> values(count);
  for (std::size_t i = 0; i < count; ++i)
    values[i] = reads_bits(fn) ? static_cast<std::uint16_t>((pdu[2 + i / 8] >> (i % 8)) & 1u) : modbus::be16(pdu, 2 + 2 * i);
  return values;
}

std::uint16_t poll_output(const MasterBlock& block, std::uint16_t request_first, std::span<const std::uint16_t> values) {
  const auto at = static_cast<std::size_t>(block.reg - request_first);
  if (block.type == ValueType::bits) {
    std::uint16_t packed = 0;
    for (std::size_t i = 0; i < block.count && i < 16; ++i)
      if (values[at + i]) packed = static_cast<std::uint16_t>(packed | (1u << i));
    return packed;
  }
  // The seed's plain copy (MBS_F04): a WORD at scale 1 goes over as it is.
  if (block.type == ValueType::word && block.scale == 1.0) return values[at];
  const double value = decode_value(block.type, block.order, values.subspan(at, register_span(block.type)));
  return to_bridge_register(value, block.scale, is_signed(block.type));
}

std::vector<std::uint16_t> send_values(const MasterBlock& block, std::uint16_t raw) {
  if (block.type == ValueType::bits) return {static_cast<std::uint16_t>(raw != 0)};
  if (block.type == ValueType::word && block.scale == 1.0) return {raw};  // MBS_F06: a plain copy
  std::vector<std::uint16_t> values(register_span(block.type));
  encode_value(block.type, block.order, from_bridge_register(raw, is_signed(block.type), block.scale), values);
  return values;
}

}  // namespace unima::master
