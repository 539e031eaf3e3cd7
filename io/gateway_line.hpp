#pragma once
// The runtime's end of the gateway (SPEC §14): the TCP and TLS ports hold this, and it
// hands their requests to the line of the master that runs now. A reload swaps masters
// under it (MasterService attaches the new one at commit), so a port never holds a master
// that is gone; while none runs (its line could not be opened), every request is answered
// 0x0B, "gateway target failed": nothing behind the gateway answers.

#include "io/gateway_request.hpp"
#include "platform/asio.hpp"

namespace unima::io {

class GatewayLine final : public LineGateway {
 public:
  explicit GatewayLine(asio::io_context& io) : io_(io) {}

  /// From now on requests go to `line`; nullptr: to none.
  void attach(LineGateway* line) { line_ = line; }

  void forward(GatewayRequest request, GatewayAnswer answer) override;
  void client_gone(std::uint64_t client) override;

 private:
  asio::io_context& io_;
  LineGateway* line_ = nullptr;
};

}  // namespace unima::io
