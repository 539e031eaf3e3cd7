#include "master/gateway_queue.hpp"

#include <algorithm>
#include <utility>

namespace unima::master {

namespace {

// Of the requests that `take`, the one whose key comes first after `last`, else (the round
// is over) the one whose key comes first: the one rule of taking turns, for hosts and for
// a host's connections alike. Among requests with one key, the oldest.
template <typename Key, typename Take, typename KeyOf>
const GatewayQueue::Request* next_in_round(const std::deque<GatewayQueue::Request>& queue, const std::optional<Key>& last,
                                           Take take, KeyOf key_of) {
  const GatewayQueue::Request* after = nullptr;
  const GatewayQueue::Request* lowest = nullptr;
  for (const auto& r : queue) {
    if (!take(r)) continue;
    const auto& key = key_of(r);
    if (!lowest || key < key_of(*lowest)) lowest = &r;
    if (last && key > *last && (!after || key < key_of(*after))) after = &r;
  }
  return after ? after : lowest;
}

}  // namespace

std::optional<GatewayQueue::Ticket> GatewayQueue::push(const Asker& asker, std::uint8_t unit, TimePoint now) {
  if (!asker.priority) {
    auto& host = hosts_[asker.host];
    if (host.waiting >= most_waiting_per_host) return std::nullopt;
    ++host.waiting;
  }
  const auto ticket = next_ticket_++;
  queue_.push_back(Request{ticket, asker.client, asker.host, asker.priority, unit, now});
  return ticket;
}

std::optional<GatewayQueue::Request> GatewayQueue::next(bool poll_due) const {
  for (const auto& r : queue_)
    if (r.priority) return r;
  if (queue_.empty() || (poll_due && !last_was_poll_)) return std::nullopt;
  const auto any = [](const Request&) { return true; };
  const auto* host = next_in_round(queue_, last_host_, any, [](const Request& r) -> const std::string& { return r.host; });
  const auto& name = host->host;
  const auto of_host = [&](const Request& r) { return r.host == name; };
  const auto* turn = next_in_round(queue_, hosts_.at(name).last_client, of_host,
                                   [](const Request& r) -> const std::uint64_t& { return r.client; });
  return *turn;
}

void GatewayQueue::began(Ticket ticket) {
  const auto it = std::find_if(queue_.begin(), queue_.end(), [&](const Request& r) { return r.ticket == ticket; });
  if (it == queue_.end()) return;
  // A priority peer's request jumps the round without taking another client's turn.
  if (!it->priority) {
    const auto previous = std::exchange(last_host_, it->host);
    hosts_[it->host].last_client = it->client;
    if (previous && *previous != it->host) forget_if_idle(*previous);
    last_was_poll_ = false;
  }
  left(*it);
  queue_.erase(it);
}

void GatewayQueue::left(const Request& request) {
  if (request.priority) return;
  const auto host = hosts_.find(request.host);
  if (host == hosts_.end()) return;
  --host->second.waiting;
  forget_if_idle(request.host);
}

// The map holds the hosts with requests waiting, and the host served last (whose round
// among its connections goes on when it asks again): never more than the queue holds + 1.
void GatewayQueue::forget_if_idle(const std::string& name) {
  const auto host = hosts_.find(name);
  if (host != hosts_.end() && host->second.waiting == 0 && name != last_host_) hosts_.erase(host);
}

std::vector<GatewayQueue::Request> GatewayQueue::expire(TimePoint now) {
  std::vector<Request> expired;
  std::erase_if(queue_, [&](const Request& r) {
    if (now - r.queued < wait_) return false;
    left(r);
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
    left(r);
    dropped.push_back(r);
    return true;
  });
  return dropped;
}

std::size_t GatewayQueue::waiting_for(std::uint8_t unit) const {
  return static_cast<std::size_t>(std::count_if(queue_.begin(), queue_.end(), [&](const Request& r) { return r.unit == unit; }));
}

}  // namespace unima::master
