#include "modbus/request_handler.hpp"
#include "modbus/bytes.hpp"

#include <algorithm>
#include <array>
#include <optional>
#include <string_view>

namespace unima::modbus {

namespace {

std::size_t read_registers(std::span<const std::uint8_t> req, std::span<std::uint8_t> rsp, RegisterModel& registers,
                           const HandlerOptions& options) {
  const std::uint8_t fn = req[0];
  if (req.size() != 5) return write_exception(fn, ExceptionCode::illegal_data_value, rsp);
  const std::uint16_t first = be16(req, 1);
  const std::uint16_t count = be16(req, 3);
  // Seed §5.3 note 1: a wrong register count is "illegal data address", not "value".
  if (count == 0 || count > options.max_read_registers || first + count > 0x10000)
    return write_exception(fn, ExceptionCode::illegal_data_address, rsp);
  std::array<std::uint16_t, max_read_registers_rtu> values;
  if (!registers.read_registers(first, std::span(values.data(), count)))
    return write_exception(fn, ExceptionCode::illegal_data_address, rsp);
  rsp[0] = fn;
  rsp[1] = static_cast<std::uint8_t>(2 * count);
  for (std::size_t i = 0; i < count; ++i) put_be16(rsp, 2 + 2 * i, values[i]);
  return 2 + 2 * std::size_t{count};
}

// The exception a refused write is answered with; nullopt when it was written.
std::optional<ExceptionCode> refusal_of(const WriteResult& result) {
  switch (result.status) {
    case WriteResult::Status::written: return std::nullopt;
    case WriteResult::Status::not_allowed: return ExceptionCode::illegal_function;
    case WriteResult::Status::read_only: return ExceptionCode::illegal_function;
    case WriteResult::Status::not_writable: return ExceptionCode::illegal_data_address;
    case WriteResult::Status::not_kept: return ExceptionCode::server_device_failure;
  }
  return ExceptionCode::illegal_data_address;
}

Handled write_single_register(std::span<const std::uint8_t> req, std::span<std::uint8_t> rsp,
                              RegisterModel& registers, const WriteRights* rights) {
  const std::uint8_t fn = req[0];
  if (req.size() != 5) return {write_exception(fn, ExceptionCode::illegal_data_value, rsp)};
  const std::uint16_t value = be16(req, 3);
  const auto result = registers.write_registers(be16(req, 1), std::span(&value, 1), rights);
  if (const auto refusal = refusal_of(result)) return {write_exception(fn, *refusal, rsp)};
  std::copy(req.begin(), req.end(), rsp.begin());  // the echo of seed §5.2
  return {req.size(), result.kept_as};
}

Handled write_multiple_registers(std::span<const std::uint8_t> req, std::span<std::uint8_t> rsp,
                                 RegisterModel& registers, const WriteRights* rights) {
  const std::uint8_t fn = req[0];
  if (req.size() < 6) return {write_exception(fn, ExceptionCode::illegal_data_value, rsp)};
  const std::uint16_t first = be16(req, 1);
  const std::uint16_t count = be16(req, 3);
  if (count == 0 || count > max_write_registers || first + count > 0x10000)
    return {write_exception(fn, ExceptionCode::illegal_data_address, rsp)};
  if (req[5] != 2 * count || req.size() != 6 + std::size_t{req[5]})
    return {write_exception(fn, ExceptionCode::illegal_data_value, rsp)};
  std::array<std::uint16_t, max_write_registers> values;
  for (std::size_t i = 0; i < count; ++i) values[i] = be16(req, 6 + 2 * i);
  const auto result = registers.write_registers(first, std::span(values.data(), count), rights);
  if (const auto refusal = refusal_of(result)) return {write_exception(fn, *refusal, rsp)};
  std::copy_n(req.begin(), 5, rsp.begin());
  return {5, result.kept_as};
}

// Function 43 / MEI 14 (Modbus Application Protocol V1.1b3 §6.21).
std::size_t read_device_identification(std::span<const std::uint8_t> req, std::span<std::uint8_t> rsp,
                                       const DeviceIdentity& identity) {
  const std::uint8_t fn = req[0];
  if (req.size() < 2 || req[1] != mei_read_device_identification)
    return write_exception(fn, ExceptionCode::illegal_function, rsp);
  if (req.size() != 4) return write_exception(fn, ExceptionCode::illegal_data_value, rsp);
  const std::uint8_t read_code = req[2];
  std::uint8_t object_id = req[3];
  const std::array<std::string_view, 7> objects = {identity.vendor_name,   identity.product_code,
                                                   identity.revision,      identity.vendor_url,
                                                   identity.product_name,  identity.model_name,
                                                   identity.user_application_name};
  std::uint8_t last_object = 0;
  switch (read_code) {
    case 1: last_object = 2; break;  // basic
    case 2:                          // regular
    case 3: last_object = 6; break;  // extended: this device has no objects past the regular ones
    case 4:
      if (object_id > 6) return write_exception(fn, ExceptionCode::illegal_data_address, rsp);
      last_object = object_id;
      break;
    default: return write_exception(fn, ExceptionCode::illegal_data_value, rsp);
  }
  if (object_id > last_object) object_id = 0;  // the specification's restart at the first object
  rsp[0] = fn;
  rsp[1] = mei_read_device_identification;
  rsp[2] = read_code;
  rsp[3] = 0x82;  // conformity: regular identification, stream and individual access
  rsp[4] = 0x00;  // more follows: everything fits in one response
  rsp[5] = 0x00;  // next object id
  std::size_t at = 7;
  std::uint8_t listed = 0;
  for (std::uint8_t id = object_id; id <= last_object; ++id) {
    const auto& value = objects[id];
    const std::size_t length = std::min<std::size_t>(value.size(), 64);
    if (at + 2 + length > max_pdu_size) break;
    rsp[at++] = id;
    rsp[at++] = static_cast<std::uint8_t>(length);
    std::copy_n(value.begin(), length, rsp.begin() + static_cast<std::ptrdiff_t>(at));
    at += length;
    ++listed;
  }
  rsp[6] = listed;
  return at;
}

}  // namespace

std::size_t write_exception(std::uint8_t function, ExceptionCode code, std::span<std::uint8_t> response) {
  response[0] = static_cast<std::uint8_t>(function | function::exception_flag);
  response[1] = static_cast<std::uint8_t>(code);
  return 2;
}

std::size_t answer_refused_write(std::uint8_t function, WriteResult::Status why, std::span<std::uint8_t> response) {
  const auto refusal = refusal_of({why});
  return write_exception(function, refusal.value_or(ExceptionCode::server_device_failure), response);
}

ExceptionCode exception_of(std::span<const std::uint8_t> response) {
  if (response.size() >= 2 && (response[0] & function::exception_flag)) return static_cast<ExceptionCode>(response[1]);
  return ExceptionCode::none;
}

Handled handle_request(std::span<const std::uint8_t> request, std::span<std::uint8_t> response,
                       RegisterModel& registers, const HandlerOptions& options, const WriteRights* rights) {
  const std::uint8_t fn = request[0];
  switch (fn) {
    case function::read_input_registers: return {read_registers(request, response, registers, options)};
    case function::write_single_register: return write_single_register(request, response, registers, rights);
    case function::read_holding_registers:
      if (options.read_holding_registers) return {read_registers(request, response, registers, options)};
      break;
    case function::write_multiple_registers:
      if (options.write_multiple_registers) return write_multiple_registers(request, response, registers, rights);
      break;
    case function::encapsulated_interface:
      if (options.device_identification) return {read_device_identification(request, response, options.identity)};
      break;
    default: break;
  }
  return {write_exception(fn, ExceptionCode::illegal_function, response)};
}

}  // namespace unima::modbus
