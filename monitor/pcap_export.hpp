#pragma once
// The monitor log's transactions as Wireshark's exported PDUs (SPEC §20): which dissector,
// which direction, which bytes. Pure: a parsed monitor line in, pcap records out.
//
// Who is who, as the exported PDU's address and port tags say it (the log holds neither
// the bridge's own address nor the line's stations', so those are made up and always
// the same): the client sends the query, the server port 502 answers it.
//   tcp:<ip>:<port>, tls:<who>@<ip>:<port>   client: that TCP client; server: the bridge
//   gw:<ip>:<port>                           client: the TCP client the bridge forwarded for
//   rtu, master                              client: the line's master (the bridge for
//                                            master), 0.0.0.0 port 0
// and the server is the unit addressed: 0.0.0.<unit> (::<unit> for an IPv6 client), so
// that Wireshark's conversations are one a client and unit.
// The frames are the wire's: the log holds every byte of an RTU frame (address, PDU, CRC)
// and every field of an MBAP header (TrID, PtID, Len, and Ad as the unit id), so nothing of
// a frame is made up, a wrong length or CRC included.

#include <optional>
#include <string>
#include <string_view>

#include "monitor/monitor_line.hpp"
#include "monitor/pcap_writer.hpp"

namespace unima::monitor {

inline constexpr std::uint16_t modbus_server_port = 502;

/// The dissector and the two ends of a transaction's frames.
struct PcapConversation {
  std::string_view dissector;  // "mbtcp" (MBAP frames) or "mbrtu" (RTU frames, CRC included)
  IpEndpoint client;
  IpEndpoint server;
};

/// The conversation of a transaction line; nullopt for a drop notice.
std::optional<PcapConversation> pcap_conversation(const MonitorLine& line);

/// Appends the records of one line: the query, then the response when one was sent or
/// heard, both at the line's time (the monitor keeps one time a transaction), each as it
/// was on the wire, a bad CRC or length included. Nothing for a drop notice, nor for a
/// Cached line (the gateway's cache answered: nothing went on the line then); no query
/// record when the log does not hold its bytes (a TCP frame too short for its header).
void append_pcap_records(std::string& out, const MonitorLine& line);

}  // namespace unima::monitor
