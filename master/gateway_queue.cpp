#include "master/gateway_queue.hpp"

#include <algorithm>

namespace unima::master {

GatewayQueue::Ticket GatewayQueue::push(std::uint64_t client, bool priority, std::uint8_t unit, TimePoint now) {
  const auto ticket = next_ticket_++;
  queue_.push_back(Request{ticket, client, priority, unit, now});
  return ticket;
}

std::optional<GatewayQueue::Request> GatewayQueue::next(bool poll_due) const {
  for (const auto& r : queue_)
    if (r.priority) return r;
  if (queue_.empty() || (poll_due && !last_was_poll_)) return std::nullopt;
  // The round goes by client number: the first client after the one served last, else
  // (the round is over) the lowest; each client's oldest request.
  const Request* after = nullptr;
  const Request* lowest = nullptr;
  for (const auto& r : queue_) {
    if (!lowest || r.client < lowest->client) lowest = &r;
    if (last_client_ && r.client > *last_client_ && (!after || r.client < after->client)) after = &r;
  }
  return after ? *after : *lowest;
}

void GatewayQueue::began(Ticket ticket) {
  const auto it = std::find_if(queue_.begin(), queue_.end(), [&](const Request& r) { return r.ticket == ticket; });
  if (it == queue_.end()) return;
  // A priority peer's request jumps the round without taking another client's turn.
  if (!it->priority) {
    last_client_ = it->client;
    last_was_poll_ = false;
  }
  queue_.erase(it);
}

std::vector<GatewayQueue::Request> GatewayQueue::expire(TimePoint now) {
  std::vector<Request> expired;
  std::erase_if(queue_, [&](const Request& r) {
    if (now - r.queued < wait_) return false;
    expired.push_back(r);
    return true;
  });
  return expired;
}

std::optional<GatewayQueue::TimePoint> GatewayQueue::next_expiry() const {
  std::optional<TimePoint> earliest;
  for (const auto& r : queue_)
    if (!earliest || r.queued < *earliest) earliest = r.queued;
  if (!earliest) return std::nullopt;
  return *earliest + wait_;
}

std::vector<GatewayQueue::Request> GatewayQueue::drop_client(std::uint64_t client) {
  std::vector<Request> dropped;
  std::erase_if(queue_, [&](const Request& r) {
    if (r.client != client) return false;
    dropped.push_back(r);
    return true;
  });
  return dropped;
}

std::size_t GatewayQueue::waiting_for(std::uint8_t unit) const {
  return static_cast<std::size_t>(std::count_if(queue_.begin(), queue_.end(), [&](const Request& r) { return r.unit == unit; }));
}

}  // namespace unima::master
