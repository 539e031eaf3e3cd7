#pragma once
// Loopback sockets the integration tests and the peers in tests/support/peers talk to the
// daemon over: a free port, waiting for a listener, and a blocking stream socket whose
// every read has a deadline, so that a daemon that does not answer fails the test instead
// of hanging it.

#include <chrono>
#include <cstdint>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace unima::test_support {

using Bytes = std::vector<std::uint8_t>;

/// A loopback TCP port that was free a moment ago, below the kernel's ephemeral range.
std::uint16_t free_port();

/// Waits until `fd` (a socket or a pty) has something to read or `deadline` passes (it
/// looks at least once), then reads once into `buf`: the count read, 0 when nothing came
/// in time, -1 at end of stream or on an error.
long read_before(int fd, std::chrono::steady_clock::time_point deadline, std::span<std::uint8_t> buf);

/// Waits until something accepts TCP connections on 127.0.0.1:port.
bool wait_for_port(std::uint16_t port, std::chrono::milliseconds timeout = std::chrono::milliseconds(10000));

/// For each connection to 127.0.0.1:server_port, by its client's port: the bytes the server
/// has not read yet (its receive queue in /proc/net/tcp) — how a test knows the daemon has
/// taken a request in without a time threshold.
std::map<std::uint16_t, unsigned long> unread_by_server(std::uint16_t server_port);
class Socket;
/// True when the server on 127.0.0.1:server_port has read all that `client` sent.
bool server_read_all(std::uint16_t server_port, const Socket& client);

/// A blocking stream socket with receive deadlines.
class Socket {
 public:
  static Socket tcp(std::uint16_t port);  // 127.0.0.1
  /// From `source` (any address of 127/8: Linux routes all of it on lo), a host other than
  /// 127.0.0.1 as far as the daemon can tell.
  static Socket tcp_from(const std::string& source, std::uint16_t port);
  static Socket unix_socket(const std::string& path);
  Socket(Socket&& other) noexcept;
  Socket& operator=(Socket&&) = delete;
  ~Socket();

  bool valid() const { return fd_ >= 0; }
  int fd() const { return fd_; }
  /// The port this end is bound to.
  std::uint16_t local_port() const;
  /// True when a read would not block now (bytes, or the peer's end).
  bool readable_now() const;
  /// Closes it now (the destructor would later).
  void close();
  void send(const Bytes& bytes) const;
  void send(const std::string& text) const;
  /// Exactly n bytes, or fewer if the peer closed or the deadline passed.
  Bytes receive(std::size_t n, std::chrono::milliseconds timeout = std::chrono::milliseconds(3000)) const;
  /// True when the peer closed the connection within `timeout`.
  bool closed_by_peer(std::chrono::milliseconds timeout = std::chrono::milliseconds(3000)) const;
  /// One line without its "\n", or nullopt at the deadline or when closed.
  std::optional<std::string> read_line(std::chrono::milliseconds timeout = std::chrono::milliseconds(3000));
  /// Reads lines until one equals `line`; false at the deadline.
  bool wait_for_line(const std::string& line, std::chrono::milliseconds timeout = std::chrono::milliseconds(5000));

 private:
  explicit Socket(int fd) : fd_(fd) {}
  int fd_ = -1;
  std::string buffered_;
};

}  // namespace unima::test_support
