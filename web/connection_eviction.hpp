#pragma once
// Which connection of a full HTTP server (`http.max_clients`) closes for a newcomer
// (issue 43, finding 7). Closing the one idle the longest let a flood lock the real user
// out: a login waiting for its password check had sent nothing for longest, so it was
// closed for the next guesser, and one host's dozens of connections pushed out everyone
// else's. So:
// - a connection with a request in progress (read, and its answer not yet written: a
//   password check it waits for, an answer being written) never gives way: its client is
//   waiting for something it asked for, and it ends by itself within the request's
//   deadline;
// - of the others, one of the host holding the most connections goes, so that a host
//   pays for its own crowd, the one idle the longest among those of the tied hosts.
// When every connection has a request in progress, none goes: the newcomer is the one
// turned away.
//
// Pure: the caller says what each connection is doing.

#include <chrono>
#include <cstddef>
#include <optional>
#include <span>
#include <string_view>

namespace unima::web {

struct OpenConnection {
  using Clock = std::chrono::steady_clock;
  std::string_view host;             // the peer's address, without its port
  Clock::time_point last_activity;   // its last request read or answer written
  bool request_in_progress = false;  // read and not yet answered
};

/// The index in `open` of the connection that closes for a newcomer; nullopt when each has
/// a request in progress.
std::optional<std::size_t> connection_to_evict(std::span<const OpenConnection> open);

}  // namespace unima::web
