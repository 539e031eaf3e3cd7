#include "modbus/capture.hpp"

#include "modbus/protocol.hpp"
#include "modbus/bytes.hpp"

namespace unima::modbus {

namespace {

constexpr std::size_t crc_size = 2;

// Values of registers [first, first + count) in `data` (big-endian pairs), for the rules of `device`.
std::vector<Captured> take(std::span<const CaptureRule> rules, std::uint8_t device, std::uint16_t first,
                           std::size_t count, std::span<const std::uint8_t> data, Captured::Via via) {
  std::vector<Captured> found;
  for (const auto& rule : rules) {
    if (device != broadcast_address && rule.device != device) continue;
    if (rule.reg < first || std::size_t(rule.reg - first) >= count) continue;
    found.push_back({rule.output, be16(data, 2 * std::size_t(rule.reg - first)), via});
  }
  return found;
}

}  // namespace

std::vector<Captured> captured_writes(std::span<const CaptureRule> rules, std::span<const std::uint8_t> query) {
  if (query.size() < 2 + 1 + crc_size) return {};
  const std::uint8_t device = query[0];
  const auto pdu = query.subspan(1, query.size() - 1 - crc_size);
  switch (pdu[0]) {
    case function::write_single_register:
      if (pdu.size() != 5) return {};
      return take(rules, device, be16(pdu, 1), 1, pdu.subspan(3), Captured::Via::write);
    case function::write_multiple_registers: {
      if (pdu.size() < 6) return {};
      const std::uint16_t count = be16(pdu, 3);
      if (pdu[5] != 2 * count || pdu.size() != 6 + std::size_t{pdu[5]}) return {};
      return take(rules, device, be16(pdu, 1), count, pdu.subspan(6), Captured::Via::write);
    }
    default: return {};
  }
}

std::vector<Captured> captured_reads(std::span<const CaptureRule> rules, std::span<const std::uint8_t> query,
                                     std::span<const std::uint8_t> response) {
  if (query.size() != 8 || response.size() < 5) return {};
  const std::uint8_t device = query[0];
  const std::uint8_t fn = query[1];
  if (fn != function::read_input_registers && fn != function::read_holding_registers) return {};
  if (device == broadcast_address || response[0] != device || response[1] != fn) return {};
  const std::uint16_t count = be16(query, 4);
  if (count == 0 || response[2] != 2 * count || response.size() != 3 + std::size_t{response[2]} + crc_size) return {};
  return take(rules, device, be16(query, 2), count, response.subspan(3, response[2]), Captured::Via::read);
}

}  // namespace unima::modbus
