// Fuzz target: what a foreign slave answers the bridge's master (docs/master.md), down
// io/master/master_port's path: the RTU link ends the frame where master::expected_response_length
// says, master::check_rtu_response or check_tcp_response judges it against the request,
// and a good read's values go to its poll blocks (response_values, poll_output); an
// exception 02 to a merged read splits it (split_after).
//
// Input: byte 0 chooses the function, the framing and the blocks' value types; bytes 1..5
// the request (first register, count, the slave's address); the rest is what came back.

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "fuzz/fuzz_check.hpp"
#include "master/master_codec.hpp"
#include "modbus/bytes.hpp"
#include "modbus/rtu/rtu_adu.hpp"

namespace {

using namespace unima;
using master::MasterBlock;
using master::ResponseStatus;
using master::ValueType;

constexpr std::uint8_t functions[] = {1, 2, 3, 4, 5, 6, 15, 16};

bool reads_bits(std::uint8_t fn) { return fn == 1 || fn == 2; }
bool is_read(std::uint8_t fn) { return fn <= 4; }

// The most a request of `fn` may carry (Modbus Application Protocol V1.1b3 §6).
std::uint16_t max_count(std::uint8_t fn) {
  switch (fn) {
    case 1:
    case 2: return 2000;
    case 3:
    case 4: return 125;
    case 15: return 1968;
    case 16: return 123;
    default: return 1;
  }
}

// One or two poll blocks inside the request, as the planner merges them: the first at its
// start, the last at its end.
std::vector<MasterBlock> blocks_of(std::uint8_t fn, std::uint16_t first, std::uint16_t count, std::uint8_t device,
                                   std::uint8_t choice) {
  static constexpr ValueType register_types[] = {ValueType::word, ValueType::int16, ValueType::dint,
                                                 ValueType::dword, ValueType::real};
  static constexpr double scales[] = {1.0, 0.1, 100.0, -2.5};
  std::vector<MasterBlock> blocks;
  const auto block_at = [&](std::uint16_t reg, std::uint16_t room, unsigned pick) {
    MasterBlock b;
    b.device = device;
    b.function = fn;
    b.reg = reg;
    b.scale = scales[(choice >> 2) % std::size(scales)];
    b.order = (choice & 0x40) ? master::WordOrder::high_first : master::WordOrder::low_first;
    if (reads_bits(fn)) {
      b.type = ValueType::bits;
      b.count = static_cast<std::uint16_t>(std::min<unsigned>(room, 1 + pick % 16));
    } else {
      b.type = register_types[pick % std::size(register_types)];
      if (master::register_span(b.type) > room) b.type = ValueType::word;
      b.count = static_cast<std::uint16_t>(master::register_span(b.type));
    }
    b.output = static_cast<unsigned>(blocks.size() + 1);
    blocks.push_back(b);
  };
  block_at(first, count, choice);
  const unsigned span = reads_bits(fn) ? 1 : 2;
  if (count >= 2 * span + 1) block_at(static_cast<std::uint16_t>(first + count - span), static_cast<std::uint16_t>(span), choice >> 3);
  return blocks;
}

void check_result(const master::MasterResponse& result, std::uint8_t fn, std::span<const std::uint8_t> request_pdu) {
  switch (result.status) {
    case ResponseStatus::ok:
      FUZZ_CHECK(!result.pdu.empty() && result.pdu[0] == fn);
      if (is_read(fn)) {
        const auto count = modbus::be16(request_pdu, 3);
        const std::size_t bytes = reads_bits(fn) ? (count + 7u) / 8u : 2u * count;
        FUZZ_CHECK(result.pdu.size() == 2 + bytes && result.pdu[1] == bytes);
      } else {
        FUZZ_CHECK(result.pdu.size() == 5);
      }
      FUZZ_CHECK(master::transaction_state(result) == modbus::TransactionState::done);
      FUZZ_CHECK(master::slave_answered(result));
      break;
    case ResponseStatus::exception:
      FUZZ_CHECK(result.pdu.size() == 2 && result.pdu[0] == (fn | modbus::function::exception_flag));
      FUZZ_CHECK(static_cast<std::uint8_t>(result.exception) == result.pdu[1]);
      break;
    default:
      FUZZ_CHECK(master::transaction_state(result) != modbus::TransactionState::done);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 6) return 0;
  const std::uint8_t choice = data[0];
  const std::uint8_t fn = functions[choice & 0x07];
  const bool tcp = (choice & 0x80) != 0;
  const std::uint8_t device = data[5];
  const std::uint16_t count = static_cast<std::uint16_t>(1 + modbus::be16(std::span(data, size), 3) % max_count(fn));
  const std::uint16_t first = static_cast<std::uint16_t>(
      std::min<unsigned>(modbus::be16(std::span(data, size), 1), 0x10000u - count));
  const auto response = std::span(data + 6, size - 6);

  master::Bytes request_pdu;
  std::vector<MasterBlock> blocks;
  if (is_read(fn)) {
    request_pdu = master::read_request_pdu(fn, first, count);
    blocks = blocks_of(fn, first, count, device, choice);
  } else {
    std::vector<std::uint16_t> values(fn == 15 || fn == 16 ? count : 1);
    for (std::size_t i = 0; i < values.size(); ++i) values[i] = static_cast<std::uint16_t>(i * 0x0101u * choice);
    request_pdu = master::write_request_pdu(fn, first, values);
    FUZZ_CHECK(request_pdu.size() <= modbus::max_pdu_size);
  }

  master::MasterResponse result;
  if (tcp) {
    result = master::check_tcp_response(response, device, request_pdu);
  } else {
    // The link ends the frame at the length the answer's first bytes announce.
    auto frame = response;
    if (const auto length = master::expected_response_length(response, fn)) {
      FUZZ_CHECK(*length >= 4 && *length <= modbus::max_rtu_adu_size);
      if (frame.size() >= *length) frame = frame.first(*length);
    }
    result = master::check_rtu_response(frame, device, request_pdu);
    if (result.status == ResponseStatus::ok || result.status == ResponseStatus::exception)
      FUZZ_CHECK(modbus::rtu_crc_ok(frame) && frame[0] == device);
  }
  check_result(result, fn, request_pdu);

  master::PlannedRequest request;
  request.device = device;
  request.function = fn;
  request.first = first;
  request.count = is_read(fn) ? count : static_cast<std::uint16_t>(1);
  for (std::size_t i = 0; i < blocks.size(); ++i) request.blocks.push_back(i);
  if (result.status == ResponseStatus::ok && is_read(fn)) {
    const auto values = master::response_values(result.pdu, fn, count);
    FUZZ_CHECK(values.size() == count);
    if (reads_bits(fn)) FUZZ_CHECK(std::all_of(values.begin(), values.end(), [](auto v) { return v <= 1; }));
    for (const auto& block : blocks) (void)master::poll_output(block, first, values);
  }
  // The parts of a split read cover its blocks and stay inside it.
  for (const auto& part : master::split_after(request, result, blocks)) {
    FUZZ_CHECK(part.device == device && part.function == fn && part.count >= 1);
    FUZZ_CHECK(part.first >= first && std::uint32_t{part.first} + part.count <= std::uint32_t{first} + count);
  }
  return 0;
}
