// Fuzz target: what a Modbus TCP client sends, down the TCP slave's path
// (io/modbus/tcp_slave_server's process()): modbus::parse_tcp_adu cuts the stream into ADUs,
// recipient_of and serve_request answer each one against the banks of
// config/examples/four-devices.yaml, and the monitor's capture rule reads the exchange.
//
// Input: byte 0 sets up the slave (its unit id, the extensions of SPEC §3 on or off);
// the rest is the stream, as one read of the socket.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "fuzz/bridge_banks.hpp"
#include "fuzz/fuzz_check.hpp"
#include "modbus/bytes.hpp"
#include "modbus/mbap.hpp"
#include "modbus/register_capture.hpp"
#include "modbus/slave_session.hpp"

namespace {

using namespace unima;
using modbus::TcpAdu;

void check_adu(const TcpAdu& adu, std::span<const std::uint8_t> bytes) {
  switch (adu.status) {
    case TcpAdu::Status::need_more:
      FUZZ_CHECK(bytes.size() < modbus::mbap_header_size || bytes.size() < modbus::mbap_header_size - 1u + adu.header.length);
      break;
    case TcpAdu::Status::bad_header:
      FUZZ_CHECK(adu.header.protocol_id != 0 || adu.header.length < modbus::mbap_min_length ||
                 adu.header.length > modbus::mbap_max_length);
      break;
    case TcpAdu::Status::complete:
      FUZZ_CHECK(adu.size == modbus::mbap_header_size - 1u + adu.header.length);
      FUZZ_CHECK(adu.size <= bytes.size() && adu.size <= modbus::max_tcp_adu_size);
      FUZZ_CHECK(!adu.pdu.empty() && adu.pdu.size() == adu.header.length - 1u);
      FUZZ_CHECK(adu.pdu.data() == bytes.data() + modbus::mbap_header_size);
      break;
  }
}

// The objects of a 43/14 answer fill it exactly (Modbus Application Protocol V1.1b3 §6.21).
void check_device_identification(std::span<const std::uint8_t> response) {
  FUZZ_CHECK(response.size() >= 7 && response[1] == modbus::mei_read_device_identification);
  std::size_t at = 7;
  for (unsigned object = 0; object < response[6]; ++object) {
    FUZZ_CHECK(at + 2 <= response.size());
    at += 2 + response[at + 1];
  }
  FUZZ_CHECK(at == response.size());
}

// What the handler's answer must look like for the request it answers.
void check_answer(std::span<const std::uint8_t> request, std::span<const std::uint8_t> response,
                  const modbus::HandlerOptions& options) {
  const std::uint8_t fn = request[0];
  FUZZ_CHECK(response.size() >= 2 && response.size() <= modbus::max_pdu_size);
  if (response[0] & modbus::function::exception_flag) {
    FUZZ_CHECK(response[0] == (fn | modbus::function::exception_flag) && response.size() == 2);
    FUZZ_CHECK(response[1] >= 0x01 && response[1] <= 0x03);  // 04 is never the handler's
    return;
  }
  FUZZ_CHECK(response[0] == fn);
  switch (fn) {
    case modbus::function::read_holding_registers:
    case modbus::function::read_input_registers: {
      FUZZ_CHECK(request.size() == 5);
      const auto count = modbus::be16(request, 3);
      FUZZ_CHECK(count >= 1 && count <= options.max_read_registers);
      FUZZ_CHECK(response[1] == 2 * count && response.size() == 2u + 2u * count);
      break;
    }
    case modbus::function::write_single_register:
      FUZZ_CHECK(std::equal(request.begin(), request.end(), response.begin(), response.end()));  // the echo
      break;
    case modbus::function::write_multiple_registers:
      FUZZ_CHECK(response.size() == 5 && std::equal(response.begin(), response.end(), request.begin()));
      break;
    case modbus::function::encapsulated_interface: check_device_identification(response); break;
    default: FUZZ_CHECK(false && "a function the handler does not serve was answered normally");
  }
}

// A register written by function 6 reads back as written, wherever it can be read at all
// (W with readable_write_banks; write blocks are write-only).
void check_written(fuzz::BridgeBanks& banks, std::span<const std::uint8_t> request) {
  std::uint16_t value = 0;
  if (banks.space.read(modbus::be16(request, 1), std::span(&value, 1))) FUZZ_CHECK(value == modbus::be16(request, 3));
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const std::uint8_t setup = data[0];
  modbus::HandlerOptions options;
  options.max_read_registers = modbus::max_read_registers_tcp;
  options.read_holding_registers = !(setup & 0x01);
  options.write_multiple_registers = !(setup & 0x02);
  options.device_identification = !(setup & 0x04);
  const std::uint8_t own_unit = (setup & 0x08) ? 17 : 1;

  fuzz::BridgeBanks banks(fuzz::example("four-devices.yaml"));
  if (setup & 0x10) banks.bring_plant_online();

  const auto stream = std::span(data + 1, size - 1);
  // Exactly the size the server gives each answer: ASan sees any byte written past it.
  std::vector<std::uint8_t> adu_out(modbus::max_tcp_adu_size);
  std::size_t at = 0;
  while (true) {
    const auto rest = stream.subspan(at);
    const auto adu = modbus::parse_tcp_adu(rest);
    check_adu(adu, rest);
    if (adu.status != TcpAdu::Status::complete) break;

    const auto unit = adu.header.unit_id;
    const auto recipient = modbus::recipient_of(modbus::Link::tcp, unit, own_unit);
    FUZZ_CHECK(recipient != modbus::Recipient::broadcast);  // TCP has none
    const auto pdu_out = std::span(adu_out).subspan(modbus::mbap_header_size, modbus::max_pdu_size);
    const auto served = modbus::serve_request(modbus::Link::tcp, recipient, adu.pdu, pdu_out, banks.model, options);
    const auto response = pdu_out.first(served.length);
    if (recipient == modbus::Recipient::this_slave) {
      check_answer(adu.pdu, response, options);
      FUZZ_CHECK(served.state == modbus::state_of_response(response));
      FUZZ_CHECK(served.fault == (served.state != modbus::TransactionState::done));
      if (adu.pdu[0] == modbus::function::write_single_register && served.state == modbus::TransactionState::done)
        check_written(banks, adu.pdu);
    } else {  // SPEC §3: another unit id is Not4Me, answered 0x0B
      FUZZ_CHECK(served.length == 2 && response[1] == 0x0B && served.fault);
      FUZZ_CHECK(served.state == modbus::TransactionState::not_for_me);
    }
    const auto size_out =
        modbus::write_mbap_header(adu.header.transaction_id, unit, served.length, adu_out) + served.length;
    FUZZ_CHECK(size_out <= modbus::max_tcp_adu_size);
    const auto answered = modbus::parse_tcp_adu(std::span<const std::uint8_t>(adu_out).first(size_out));
    FUZZ_CHECK(answered.status == TcpAdu::Status::complete && answered.size == size_out);

    // The monitor's capture indicators read the same exchange (monitor/capture_indicators).
    const modbus::Transaction transaction{modbus::PortKind::tcp, {}, {}, served.state, rest.first(adu.size),
                                          std::span<const std::uint8_t>(adu_out).first(size_out)};
    if (const auto captured = modbus::captured_registers(transaction)) {
      // A byte count (one byte) carries at most 127 registers.
      FUZZ_CHECK(captured->count() >= 1 && captured->count() <= 127 && captured->data.size() % 2 == 0);
    }
    at += adu.size;
  }
  return 0;
}
