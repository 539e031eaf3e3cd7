#include "modbus/slave_session.hpp"

namespace unima::modbus {

Recipient recipient_of(Link link, std::uint8_t address, std::uint8_t own_address) {
  if (address == own_address) return Recipient::this_slave;
  if (link == Link::tcp)
    return address == unit_id_any || address == unit_id_not_used ? Recipient::this_slave : Recipient::another_slave;
  return address == broadcast_address ? Recipient::broadcast : Recipient::another_slave;
}

Verdict route(Recipient recipient, std::uint8_t unit, std::uint8_t function,
              const std::array<bool, 256>* routed_units, const WriteRights* rights, bool reads_only) {
  if (recipient != Recipient::another_slave || !routed_units || !(*routed_units)[unit]) return Verdict::serve;
  if (reads_only && !function::only_reads(function)) return Verdict::refuse_forward;
  return !rights || rights->may_forward(unit, function) ? Verdict::forward : Verdict::refuse_forward;
}

Served serve_request(Link link, Recipient recipient, std::span<const std::uint8_t> pdu, std::span<std::uint8_t> out,
                     RegisterModel& registers, const HandlerOptions& options, const WriteRights* rights,
                     bool gateway) {
  Served served;
  switch (recipient) {
    case Recipient::this_slave: {
      const auto handled = handle_request(pdu, out, registers, options, rights);
      served.length = handled.length;
      served.kept_as = handled.kept_as;
      served.state = state_of_response(out.first(served.length));
      served.fault = served.state != TransactionState::done;
      break;
    }
    case Recipient::broadcast: {
      const auto handled = handle_request(pdu, out, registers, options, rights);
      served.kept_as = handled.kept_as;
      served.state = state_of_response(out.first(handled.length));
      break;
    }
    case Recipient::another_slave:
      served.state = TransactionState::not_for_me;
      if (link == Link::rtu) break;
      // SPEC §3: a unit id that is not ours is Not4Me, answered "gateway target failed";
      // SPEC §14: behind a gateway that does not route it, "gateway path unavailable".
      served.length = write_exception(
          pdu[0], gateway ? ExceptionCode::gateway_path_unavailable : ExceptionCode::gateway_target_failed, out);
      served.fault = true;
      break;
  }
  return served;
}

Served refuse_unkept_write(Recipient recipient, std::uint8_t function, std::span<std::uint8_t> out) {
  Served served;
  const auto length = answer_refused_write(function, WriteResult::Status::not_kept, out);
  served.state = state_of_response(out.first(length));
  if (recipient == Recipient::this_slave) {
    served.length = length;
    served.fault = true;
  }
  return served;
}

Served refuse_forwarded_write(std::uint8_t function, std::span<std::uint8_t> out) {
  Served served;
  served.length = answer_refused_write(function, WriteResult::Status::not_allowed, out);
  served.state = state_of_response(out.first(served.length));
  served.fault = true;
  return served;
}

}  // namespace unima::modbus
