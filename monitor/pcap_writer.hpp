#pragma once
// A classic pcap file of Wireshark's "exported PDU" records (SPEC §20): what `unima-bridge
// monitor --pcap` writes so that Wireshark and tshark dissect Modbus frames with no set-up.
// Pure: bytes in, bytes out; no libpcap, no I/O.
//
// File: the classic 24-byte global header (magic A1B2C3D4, written little endian, so
// microsecond time stamps; version 2.4; link type 252, LINKTYPE_WIRESHARK_UPPER_PDU), then
// one record per frame: 16-byte record header (seconds, microseconds, captured and
// original length), the exported-PDU tags, the frame.
// Tags (Wireshark's epan/exported_pdu.h): 2-byte type and 2-byte length, big endian, then
// the value, NUL-padded to a multiple of 4 bytes; the length counts the padding (Wireshark
// 4.0 steps over exactly that many bytes). In this order: 12 the dissector's name, 20/21
// (IPv4) or 22/23 (IPv6) source and destination address, 24 port type (2: TCP), 25/26
// source and destination port, 0 the end of the tags.

#include <array>
#include <chrono>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>

namespace unima::monitor {

inline constexpr std::uint32_t linktype_wireshark_upper_pdu = 252;

/// An address and port as the exported PDU's tags carry them.
struct IpEndpoint {
  std::array<std::uint8_t, 16> address{};
  bool ipv6 = false;  // address holds 16 bytes; else its first 4
  std::uint16_t port = 0;

  static IpEndpoint v4(std::array<std::uint8_t, 4> address, std::uint16_t port);
  /// "192.0.2.7" or "::1" (no brackets); nullopt when it is neither.
  static std::optional<IpEndpoint> parse(std::string_view address, std::uint16_t port);
};

/// One frame as Wireshark's exported PDU carries it to the dissector named.
struct ExportedPdu {
  std::chrono::system_clock::time_point time;
  std::string_view dissector;  // Wireshark's name for it: "mbtcp", "mbrtu"
  IpEndpoint source;
  IpEndpoint destination;
  std::span<const std::uint8_t> frame;
};

/// Appends the global header, once at the start of the file.
void append_pcap_header(std::string& out);
/// Appends one record. A time before 1970 is written as 1970.
void append_pcap_record(std::string& out, const ExportedPdu& pdu);

}  // namespace unima::monitor
