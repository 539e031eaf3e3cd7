#include "modbus/adu_view.hpp"

#include "modbus/bytes.hpp"

namespace unima::modbus {

Framing framing_of(const Transaction& transaction) {
  switch (transaction.port) {
    case PortKind::tcp:
    case PortKind::tls: return Framing::tcp;
    case PortKind::rtu:
    case PortKind::gateway: return Framing::rtu;  // the frames on the master's RTU line
    case PortKind::master: return transaction.peer.empty() ? Framing::rtu : Framing::tcp;
  }
  return Framing::rtu;
}

AduView view_adu(std::span<const std::uint8_t> frame, Framing framing) {
  AduView view;
  if (framing == Framing::tcp) {
    if (frame.size() < mbap_header_size) return view;
    const auto header = read_mbap_header(frame);
    view.mbap = header;
    view.address = header.unit_id;
    view.pdu = frame.subspan(mbap_header_size);
    return view;
  }
  if (frame.empty()) return view;
  view.address = frame[0];
  if (frame.size() < 3) {
    view.pdu = frame.subspan(1);
    return view;
  }
  view.pdu = frame.subspan(1, frame.size() - 3);
  view.crc_on_wire = be16(frame, frame.size() - 2);
  return view;
}

std::vector<std::uint8_t> adu_bytes(const AduView& view) {
  std::vector<std::uint8_t> frame;
  if (view.mbap) {
    frame.resize(mbap_header_size);
    put_be16(frame, 0, view.mbap->transaction_id);
    put_be16(frame, 2, view.mbap->protocol_id);
    put_be16(frame, 4, view.mbap->length);
    frame[6] = view.mbap->unit_id;
  } else if (view.address) {
    frame.push_back(*view.address);
  } else {
    return frame;
  }
  frame.insert(frame.end(), view.pdu.begin(), view.pdu.end());
  if (view.crc_on_wire) {
    frame.resize(frame.size() + 2);
    put_be16(frame, frame.size() - 2, *view.crc_on_wire);
  }
  return frame;
}

}  // namespace unima::modbus
