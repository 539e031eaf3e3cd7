#include "modbus/mbap.hpp"

#include <algorithm>

#include "modbus/bytes.hpp"

namespace unima::modbus {

MbapHeader read_mbap_header(std::span<const std::uint8_t> bytes) {
  return {be16(bytes, 0), be16(bytes, 2), be16(bytes, 4), bytes[6]};
}

TcpAdu parse_tcp_adu(std::span<const std::uint8_t> bytes) {
  TcpAdu adu;
  if (bytes.size() < mbap_header_size) return adu;
  adu.header = read_mbap_header(bytes);
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
  put_be16(out, 0, transaction_id);
  put_be16(out, 2, 0);
  put_be16(out, 4, static_cast<std::uint16_t>(length));
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
