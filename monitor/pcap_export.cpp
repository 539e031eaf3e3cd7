#include "monitor/pcap_export.hpp"

#include <charconv>

#include "modbus/adu_view.hpp"

namespace unima::monitor {

namespace {

// "<ip>:<port>", the IPv6 address without brackets as the ports write it ("::1:5020").
std::optional<IpEndpoint> parse_peer(std::string_view peer) {
  const auto colon = peer.rfind(':');
  if (colon == std::string_view::npos) return std::nullopt;
  const auto port_text = peer.substr(colon + 1);
  std::uint16_t port = 0;
  const auto [end, ec] = std::from_chars(port_text.data(), port_text.data() + port_text.size(), port);
  if (port_text.empty() || ec != std::errc{} || end != port_text.data() + port_text.size()) return std::nullopt;
  return IpEndpoint::parse(peer.substr(0, colon), port);
}

// The TCP client a port name names: "tcp:…", "gw:…", "tls:<role or subject>@…".
std::optional<IpEndpoint> tcp_client_of(std::string_view kind, std::string_view peer) {
  if (kind == "tls") {
    const auto at = peer.rfind('@');
    if (at == std::string_view::npos) return std::nullopt;
    peer.remove_prefix(at + 1);
  }
  return parse_peer(peer);
}

const IpEndpoint line_master = IpEndpoint::v4({0, 0, 0, 0}, 0);

IpEndpoint unit_server(std::uint8_t unit, bool ipv6) {
  IpEndpoint server;
  server.ipv6 = ipv6;
  server.address[ipv6 ? 15 : 3] = unit;
  server.port = modbus_server_port;
  return server;
}

}  // namespace

std::optional<PcapConversation> pcap_conversation(const MonitorLine& line) {
  if (line.kind != MonitorLine::Kind::transaction) return std::nullopt;
  const std::string_view port = line.port;
  const auto colon = port.find(':');
  const auto kind = port.substr(0, colon);
  const auto peer = colon == std::string_view::npos ? std::string_view{} : port.substr(colon + 1);

  PcapConversation conversation;
  // The frames are MBAP frames where the log shows an MBAP header, and on a TCP port
  // however short they were; RTU frames otherwise (the line's, the gateway's, a master's).
  const bool mbap = line.mbap || kind == "tcp" || kind == "tls";
  conversation.dissector = mbap ? "mbtcp" : "mbrtu";
  conversation.client = line_master;
  if (kind == "tcp" || kind == "tls" || kind == "gw")
    conversation.client = tcp_client_of(kind, peer).value_or(line_master);
  conversation.server = unit_server(line.address.value_or(0), conversation.client.ipv6);
  return conversation;
}

void append_pcap_records(std::string& out, const MonitorLine& line) {
  if (line.state == modbus::TransactionState::cached) return;
  const auto conversation = pcap_conversation(line);
  if (!conversation) return;
  const auto query = modbus::adu_bytes(line.fields().query);
  if (!query.empty())
    append_pcap_record(out, {line.time, conversation->dissector, conversation->client, conversation->server, query});
  if (!line.response.empty())
    append_pcap_record(out,
                       {line.time, conversation->dissector, conversation->server, conversation->client, line.response});
}

}  // namespace unima::monitor
