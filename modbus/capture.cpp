#include "modbus/capture.hpp"

#include "modbus/protocol.hpp"
#include "modbus/register_capture.hpp"

namespace unima::modbus {

namespace {

// The values of `captured` for the rules watching its device (every rule for a broadcast).
std::vector<Captured> take(std::span<const CaptureRule> rules, const CapturedRegisters& captured, Captured::Via via) {
  std::vector<Captured> found;
  for (const auto& rule : rules) {
    if (captured.address != broadcast_address && rule.device != captured.address) continue;
    if (const auto value = captured.value_of(rule.reg)) found.push_back({rule.output, *value, via});
  }
  return found;
}

}  // namespace

std::vector<Captured> captured_writes(std::span<const CaptureRule> rules, std::span<const std::uint8_t> query) {
  const auto captured = exchange_registers(view_adu(query, Framing::rtu), {});
  if (!captured || captured->access != CaptureAccess::write) return {};
  return take(rules, *captured, Captured::Via::write);
}

std::vector<Captured> captured_reads(std::span<const CaptureRule> rules, std::span<const std::uint8_t> query,
                                     std::span<const std::uint8_t> response) {
  const auto captured = exchange_registers(view_adu(query, Framing::rtu), view_adu(response, Framing::rtu));
  if (!captured || captured->access != CaptureAccess::read) return {};
  return take(rules, *captured, Captured::Via::read);
}

}  // namespace unima::modbus
