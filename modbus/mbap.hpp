#pragma once
// Modbus TCP framing: the MBAP header (Modbus Messaging on TCP/IP Implementation Guide
// V1.0b §3.1.3). A reader fed with whatever bytes arrived, in the manner of Asio's HTTP
// request_parser: it says complete, need-more or bad, and how far it read.

#include <cstdint>
#include <span>

namespace unima::modbus {

inline constexpr std::size_t mbap_header_size = 7;  // transaction, protocol, length, unit
/// Length counts the unit id and the PDU: at least unit + function, at most unit + 253.
inline constexpr std::uint16_t mbap_min_length = 2;
inline constexpr std::uint16_t mbap_max_length = 254;
inline constexpr std::size_t max_tcp_adu_size = mbap_header_size - 1 + mbap_max_length;  // 260

struct MbapHeader {
  std::uint16_t transaction_id = 0;
  std::uint16_t protocol_id = 0;
  std::uint16_t length = 0;
  std::uint8_t unit_id = 0;
};

struct TcpAdu {
  enum class Status : std::uint8_t { complete, need_more, bad_header };
  Status status = Status::need_more;
  MbapHeader header;
  std::span<const std::uint8_t> pdu;  // when complete
  std::size_t size = 0;               // bytes the ADU takes, when complete
};

/// The seven header bytes at the start of `bytes` (at least that many), unchecked.
MbapHeader read_mbap_header(std::span<const std::uint8_t> bytes);
/// Looks for one ADU at the start of `bytes`. A header with protocol id other than 0 or a
/// length outside 2..254 is bad: the stream cannot be re-synchronised, so the connection
/// must be closed.
TcpAdu parse_tcp_adu(std::span<const std::uint8_t> bytes);

/// Writes the MBAP header of an ADU whose PDU of `pdu_size` bytes follows it in `out`
/// (at least mbap_header_size bytes): for a PDU built in place. Returns mbap_header_size.
std::size_t write_mbap_header(std::uint16_t transaction_id, std::uint8_t unit_id, std::size_t pdu_size,
                              std::span<std::uint8_t> out);

/// Writes header + pdu into `out` (at least mbap_header_size + pdu.size() bytes); the
/// length field is computed. Returns the ADU size.
std::size_t write_tcp_adu(std::uint16_t transaction_id, std::uint8_t unit_id, std::span<const std::uint8_t> pdu,
                          std::span<std::uint8_t> out);

}  // namespace unima::modbus
