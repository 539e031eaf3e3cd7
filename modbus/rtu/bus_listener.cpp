#include "modbus/rtu/bus_listener.hpp"

#include <utility>

namespace unima::modbus {

void BusListener::heard_query(std::span<const std::uint8_t> query, RtuClock::time_point now) {
  waiting_.emplace(query.begin(), query.end());
  heard_at_ = now;
}

std::optional<BusListener::Exchange> BusListener::heard_response(std::span<const std::uint8_t> response) {
  if (!waiting_) return std::nullopt;
  Exchange exchange{std::move(*waiting_), {response.begin(), response.end()}};
  waiting_.reset();
  return exchange;
}

std::optional<BusListener::Exchange> BusListener::interrupted() {
  if (!waiting_) return std::nullopt;
  Exchange exchange{std::move(*waiting_), {}};
  waiting_.reset();
  return exchange;
}

std::optional<RtuClock::time_point> BusListener::deadline() const {
  if (!waiting_) return std::nullopt;
  return heard_at_ + give_up_after_;
}

std::optional<BusListener::Exchange> BusListener::expire(RtuClock::time_point now) {
  const auto due = deadline();
  if (!due || now < *due) return std::nullopt;
  return interrupted();
}

}  // namespace unima::modbus
