#include "io/gateway_line.hpp"

#include "master/gateway.hpp"

namespace unima::io {

void GatewayLine::forward(GatewayRequest request, GatewayAnswer answer) {
  if (line_) return line_->forward(std::move(request), std::move(answer));
  // Not from within the port's call: GatewayAnswer's rule.
  asio::post(io_, [fn = request.pdu.at(0), answer = std::move(answer)] {
    answer(master::gateway_exception(fn, modbus::ExceptionCode::gateway_target_failed));
  });
}

void GatewayLine::client_gone(std::uint64_t client) {
  if (line_) line_->client_gone(client);
}

}  // namespace unima::io
