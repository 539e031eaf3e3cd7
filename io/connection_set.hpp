#pragma once
// The open connections of a server (the Modbus TCP slave, HTTP, the UnimaBUS feed): the
// set holds each alive while it is open, and a connection forgets itself when it closes.
// A server that stops takes them all out first and closes each (a close forgets, so the
// set must not be walked then); the Modbus TCP server, when full, closes the connection
// idle the longest (HTTP asks web::connection_to_evict instead).

#include <algorithm>
#include <memory>
#include <set>
#include <utility>
#include <vector>

namespace unima::io {

template <typename Connection>
class ConnectionSet {
 public:
  using Pointer = std::shared_ptr<Connection>;

  void add(Pointer connection) { connections_.insert(std::move(connection)); }
  /// A connection that closed: the set no longer holds it.
  void forget(const Connection* connection) {
    const auto it = std::find_if(connections_.begin(), connections_.end(),
                                 [connection](const Pointer& held) { return held.get() == connection; });
    if (it != connections_.end()) connections_.erase(it);
  }

  std::size_t size() const { return connections_.size(); }
  bool empty() const { return connections_.empty(); }
  auto begin() const { return connections_.begin(); }
  auto end() const { return connections_.end(); }

  /// Every connection, taken out of the set: for a server that closes them all.
  std::set<Pointer> take_all() { return std::exchange(connections_, {}); }
  /// A copy, for a walk whose steps may close connections (and so forget them).
  std::vector<Pointer> copy() const { return {connections_.begin(), connections_.end()}; }
  /// The connection whose last_activity() is the oldest; null when there is none.
  Pointer idlest() const {
    const auto it = std::min_element(connections_.begin(), connections_.end(),
                                     [](const Pointer& a, const Pointer& b) { return a->last_activity() < b->last_activity(); });
    return it == connections_.end() ? nullptr : *it;
  }

 private:
  std::set<Pointer> connections_;
};

}  // namespace unima::io
