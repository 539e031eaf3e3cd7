#include "modbus/mbap.hpp"

#include <algorithm>

namespace unima::modbus {

TcpAdu parse_tcp_adu(std::span<const std::uint8_t> bytes) {
  TcpAdu adu;
  if (bytes.size() < mbap_header_size) return adu;
  adu.header.transaction_id = static_cast<std::uint16_t>(bytes[0] << 8 | bytes[1]);
  adu.header.protocol_id = static_cast<std::uint16_t>(bytes[2] << 8 | bytes[3]);
  adu.header.length = static_cast<std::uint16_t>(bytes[4] << 8 | bytes[5]);
  adu.header.unit_id = bytes[6];
  if (adu.header.protocol_id != 0 || adu.header.length < mbap_min_length || adu.header.length > mbap_max_length) {
    adu.status = TcpAdu::Status::bad_header;
    return adu;
  }
  const std::size_t total = mbap_header_size - 1 + adu.header.length;
  if (bytes.size() < total) return adu;
  adu.status = TcpAdu::Status::complete;
  adu.pdu = bytes.subspan(mbap_header_size, total - mbap_header_size);
  adu.size = total;
  return adu;
}

std::size_t write_mbap_header(std::uint16_t transaction_id, std::uint8_t unit_id, std::size_t pdu_size,
                              std::span<std::uint8_t> out) {
  const std::size_t length = pdu_size + 1;
  out[0] = static_cast<std::uint8_t>(transaction_id >> 8);
  out[1] = static_cast<std::uint8_t>(transaction_id);
  out[2] = 0;
  out[3] = 0;
  out[4] = static_cast<std::uint8_t>(length >> 8);
  out[5] = static_cast<std::uint8_t>(length);
  out[6] = unit_id;
  return mbap_header_size;
}

std::size_t write_tcp_adu(std::uint16_t transaction_id, std::uint8_t unit_id, std::span<const std::uint8_t> pdu,
                          std::span<std::uint8_t> out) {
  write_mbap_header(transaction_id, unit_id, pdu.size(), out);
  std::copy(pdu.begin(), pdu.end(), out.begin() + mbap_header_size);
  return mbap_header_size + pdu.size();
}

}  // namespace unima::modbus
