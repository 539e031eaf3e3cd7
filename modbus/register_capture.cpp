#include "modbus/register_capture.hpp"

#include "modbus/protocol.hpp"
#include "modbus/bytes.hpp"

namespace unima::modbus {

std::optional<std::uint16_t> CapturedRegisters::value_of(std::uint16_t reg) const {
  if (reg < first || std::size_t{reg} - first >= count()) return std::nullopt;
  return be16(data, 2 * (std::size_t{reg} - first));
}

std::optional<CapturedRegisters> exchange_registers(const AduView& query, const AduView& response) {
  if (!query.address || query.pdu.empty()) return std::nullopt;
  if (!response.pdu.empty() && (response.pdu[0] & function::exception_flag)) return std::nullopt;
  const auto pdu = query.pdu;
  CapturedRegisters captured;
  captured.address = *query.address;
  switch (pdu[0]) {
    case function::write_single_register:
      if (pdu.size() != 5) return std::nullopt;
      captured.first = be16(pdu, 1);
      captured.data = pdu.subspan(3, 2);
      captured.access = CaptureAccess::write;
      return captured;
    case function::write_multiple_registers: {
      if (pdu.size() < 6) return std::nullopt;
      const std::size_t count = be16(pdu, 3);
      if (count == 0 || pdu[5] != 2 * count || pdu.size() != 6 + 2 * count) return std::nullopt;
      captured.first = be16(pdu, 1);
      captured.data = pdu.subspan(6, 2 * count);
      captured.access = CaptureAccess::write;
      return captured;
    }
    case function::read_holding_registers:
    case function::read_input_registers: {
      if (pdu.size() != 5 || captured.address == broadcast_address) return std::nullopt;
      // Only the queried slave's answer carries its registers.
      if (response.address != query.address) return std::nullopt;
      const std::size_t count = be16(pdu, 3);
      const auto rsp = response.pdu;
      if (count == 0 || rsp.size() < 2 || rsp[0] != pdu[0] || rsp[1] != 2 * count || rsp.size() != 2 + 2 * count)
        return std::nullopt;
      captured.first = be16(pdu, 1);
      captured.data = rsp.subspan(2, 2 * count);
      captured.access = CaptureAccess::read;
      return captured;
    }
    default: return std::nullopt;
  }
}

std::optional<CapturedRegisters> captured_registers(const Transaction& transaction) {
  if (transaction.state != TransactionState::done && transaction.state != TransactionState::not_for_me)
    return std::nullopt;
  const auto framing = framing_of(transaction);
  return exchange_registers(view_adu(transaction.query, framing), view_adu(transaction.response, framing));
}

}  // namespace unima::modbus
