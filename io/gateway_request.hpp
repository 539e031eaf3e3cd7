#pragma once
// A Modbus TCP client's request for a foreign slave on the master's line (modbus.gateway,
// SPEC §14): what the TCP slave hands the master, how the answer comes back, and the
// interface between the two (LineGateway).

#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

namespace unima::io {

struct GatewayRequest {
  std::uint64_t client = 0;  // the connection: its requests are one turn in the round
  std::string peer;          // "ip:port", for the monitor
  bool priority = false;     // a modbus.gateway.priority peer
  std::uint8_t unit = 0;
  std::vector<std::uint8_t> pdu;
};

/// Called once, on the event loop and never from within the call that forwarded the
/// request, with the answer PDU: the slave's own (data or its exception), or the
/// gateway's exception 0x0B or 0x06.
using GatewayAnswer = std::function<void(std::span<const std::uint8_t> pdu)>;

/// The way from the Modbus slave ports to a line of foreign slaves: the TCP and TLS ports
/// call it, the master's port (io/master/master_port) is it, io::GatewayLine joins them.
class LineGateway {
 public:
  virtual ~LineGateway() = default;
  /// Queued for the line and answered once, as GatewayAnswer says.
  virtual void forward(GatewayRequest request, GatewayAnswer answer) = 0;
  /// A client's connection closed (GatewayRequest::client): its requests still queued for
  /// the line leave the queue unanswered; one already on the line runs to its end.
  virtual void client_gone(std::uint64_t client) = 0;
};

}  // namespace unima::io
