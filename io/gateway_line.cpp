#include "io/gateway_line.hpp"

#include <algorithm>

#include "master/gateway.hpp"

namespace unima::io {

void GatewayLine::attach(const std::array<bool, 256>& units, LineGateway* line) {
  for (std::size_t unit = 0; unit < units.size(); ++unit)
    if (units[unit]) lines_[unit] = line;
}

void GatewayLine::forward(GatewayRequest request, GatewayAnswer answer) {
  if (auto* line = lines_[request.unit]) return line->forward(std::move(request), std::move(answer));
  // Not from within the port's call: GatewayAnswer's rule.
  asio::post(io_, [fn = request.pdu.at(0), answer = std::move(answer)] {
    answer(master::gateway_exception(fn, modbus::ExceptionCode::gateway_target_failed));
  });
}

void GatewayLine::client_gone(std::uint64_t client) {
  std::array<LineGateway*, 256> told{};
  std::size_t count = 0;
  for (auto* line : lines_)
    if (line && std::find(told.begin(), told.begin() + count, line) == told.begin() + count) {
      told[count++] = line;
      line->client_gone(client);
    }
}

}  // namespace unima::io
