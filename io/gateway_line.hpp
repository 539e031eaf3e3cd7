#pragma once
// The runtime's end of the gateway (SPEC §14, §18): the TCP and TLS ports hold this, and it
// hands each request to the line of the master line whose gateway routes its unit. A reload
// swaps masters under it (MasterService attaches the new ones at commit), so a port never
// holds a master that is gone; while none runs for a unit (its line could not be opened),
// a request for it is answered 0x0B, "gateway target failed": nothing behind the gateway
// answers.

#include <array>

#include "io/gateway_request.hpp"
#include "platform/asio.hpp"

namespace unima::io {

class GatewayLine final : public LineGateway {
 public:
  explicit GatewayLine(asio::io_context& io) : io_(io) {}

  /// From now on requests for `units` go to `line`; nullptr: to none.
  void attach(const std::array<bool, 256>& units, LineGateway* line);
  /// No request goes to any line any more.
  void detach_all() { lines_.fill(nullptr); }

  void forward(GatewayRequest request, GatewayAnswer answer) override;
  /// Every line hears it: the client's requests may wait on more than one.
  void client_gone(std::uint64_t client) override;

 private:
  asio::io_context& io_;
  std::array<LineGateway*, 256> lines_{};  // by unit id
};

}  // namespace unima::io
