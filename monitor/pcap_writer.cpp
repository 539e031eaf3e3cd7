#include "monitor/pcap_writer.hpp"

#include <arpa/inet.h>

#include <algorithm>

namespace unima::monitor {

namespace {

// Tag types of epan/exported_pdu.h.
enum ExportedPduTag : std::uint16_t {
  end_of_options = 0,
  dissector_name = 12,  // EXP_PDU_TAG_PROTO_NAME (EXP_PDU_TAG_DISSECTOR_NAME in newer releases)
  ipv4_source = 20,
  ipv4_destination = 21,
  ipv6_source = 22,
  ipv6_destination = 23,
  port_type = 24,
  source_port = 25,
  destination_port = 26,
};
constexpr std::uint32_t port_type_tcp = 2;  // EXP_PDU_PT_TCP
// tcpdump's default; a Modbus frame is at most 260 bytes, the tags under 100.
constexpr std::uint32_t snapshot_length = 262144;

void put_le32(std::string& out, std::uint32_t value) {
  for (int shift = 0; shift < 32; shift += 8) out.push_back(static_cast<char>(value >> shift));
}
void set_le32(std::string& out, std::size_t at, std::uint32_t value) {
  for (int i = 0; i < 4; ++i) out[at + static_cast<std::size_t>(i)] = static_cast<char>(value >> (8 * i));
}
void put_le16(std::string& out, std::uint16_t value) {
  out.push_back(static_cast<char>(value));
  out.push_back(static_cast<char>(value >> 8));
}
void put_be16(std::string& out, std::uint16_t value) {
  out.push_back(static_cast<char>(value >> 8));
  out.push_back(static_cast<char>(value));
}
void put_be32(std::string& out, std::uint32_t value) {
  for (int shift = 24; shift >= 0; shift -= 8) out.push_back(static_cast<char>(value >> shift));
}

std::size_t padded(std::size_t size) { return (size + 3) & ~std::size_t{3}; }

void put_tag(std::string& out, ExportedPduTag tag, std::span<const std::uint8_t> value) {
  put_be16(out, tag);
  put_be16(out, static_cast<std::uint16_t>(padded(value.size())));
  out.append(reinterpret_cast<const char*>(value.data()), value.size());
  out.append(padded(value.size()) - value.size(), '\0');
}
void put_tag(std::string& out, ExportedPduTag tag, std::uint32_t value) {
  put_be16(out, tag);
  put_be16(out, 4);
  put_be32(out, value);
}
void put_address_tag(std::string& out, bool source, const IpEndpoint& endpoint) {
  const auto tag = endpoint.ipv6 ? (source ? ipv6_source : ipv6_destination) : (source ? ipv4_source : ipv4_destination);
  put_tag(out, tag, std::span<const std::uint8_t>(endpoint.address.data(), endpoint.ipv6 ? 16 : 4));
}

}  // namespace

IpEndpoint IpEndpoint::v4(std::array<std::uint8_t, 4> address, std::uint16_t port) {
  IpEndpoint endpoint;
  std::copy(address.begin(), address.end(), endpoint.address.begin());
  endpoint.port = port;
  return endpoint;
}

std::optional<IpEndpoint> IpEndpoint::parse(std::string_view address, std::uint16_t port) {
  const std::string text(address);  // inet_pton wants its terminating NUL
  IpEndpoint endpoint;
  endpoint.port = port;
  if (inet_pton(AF_INET, text.c_str(), endpoint.address.data()) == 1) return endpoint;
  endpoint.ipv6 = true;
  if (inet_pton(AF_INET6, text.c_str(), endpoint.address.data()) == 1) return endpoint;
  return std::nullopt;
}

void append_pcap_header(std::string& out) {
  put_le32(out, 0xA1B2C3D4);  // microsecond time stamps, and the byte order of what follows
  put_le16(out, 2);           // version 2.4
  put_le16(out, 4);
  put_le32(out, 0);  // time zone: UTC
  put_le32(out, 0);  // accuracy of the time stamps: unstated, as everyone writes it
  put_le32(out, snapshot_length);
  put_le32(out, linktype_wireshark_upper_pdu);
}

void append_pcap_record(std::string& out, const ExportedPdu& pdu) {
  using namespace std::chrono;
  const auto since_epoch = std::max(floor<microseconds>(pdu.time).time_since_epoch(), microseconds(0));
  const auto seconds = floor<std::chrono::seconds>(since_epoch);
  const auto header_at = out.size();
  put_le32(out, static_cast<std::uint32_t>(seconds.count()));
  put_le32(out, static_cast<std::uint32_t>((since_epoch - seconds).count()));
  put_le32(out, 0);  // lengths, once known
  put_le32(out, 0);
  const auto data_at = out.size();
  put_tag(out, dissector_name,
          std::span<const std::uint8_t>(reinterpret_cast<const std::uint8_t*>(pdu.dissector.data()), pdu.dissector.size()));
  put_address_tag(out, true, pdu.source);
  put_address_tag(out, false, pdu.destination);
  put_tag(out, port_type, port_type_tcp);
  put_tag(out, source_port, pdu.source.port);
  put_tag(out, destination_port, pdu.destination.port);
  put_be16(out, end_of_options);
  put_be16(out, 0);
  out.append(reinterpret_cast<const char*>(pdu.frame.data()), pdu.frame.size());
  const auto length = static_cast<std::uint32_t>(out.size() - data_at);
  set_le32(out, header_at + 8, length);   // captured
  set_le32(out, header_at + 12, length);  // on the wire: all of it was kept
}

}  // namespace unima::monitor
