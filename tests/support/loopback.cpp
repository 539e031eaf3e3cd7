#include "tests/support/loopback.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <stdexcept>

#include "tests/support/eventually.hpp"

namespace unima::test_support {

using namespace std::chrono_literals;

namespace {
sockaddr_in loopback(std::uint16_t port) {
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(port);
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  return addr;
}
}  // namespace

namespace {

bool bindable(std::uint16_t port) {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  auto addr = loopback(port);
  const bool ok = ::bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) == 0;
  ::close(fd);
  return ok;
}

// The first port the kernel hands out to connecting sockets (32768 by default).
std::uint16_t ephemeral_low() {
  std::ifstream range("/proc/sys/net/ipv4/ip_local_port_range");
  unsigned low = 0;
  return range >> low && low > 0 && low <= 65535 ? static_cast<std::uint16_t>(low) : 32768;
}

}  // namespace

// Below the ephemeral range: a port from bind(0) may become another test's client socket's
// local port before the daemon binds it ("Address already in use"); one down here stays
// free. Each test process starts at its own place in the range, so parallel tests rarely
// try the same port.
std::uint16_t free_port() {
  constexpr unsigned first = 10000;
  const unsigned low = ephemeral_low();
  if (low <= first + 1000) {  // an unusual range: fall back to the kernel's choice
    const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
    auto addr = loopback(0);
    if (::bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) throw std::runtime_error("bind");
    socklen_t len = sizeof addr;
    ::getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &len);
    ::close(fd);
    return ntohs(addr.sin_port);
  }
  const unsigned span = low - first;
  static unsigned next = static_cast<unsigned>(::getpid()) * 7919u % span;
  for (unsigned tries = 0; tries < span; ++tries) {
    const auto port = static_cast<std::uint16_t>(first + next++ % span);
    if (bindable(port)) return port;
  }
  throw std::runtime_error("no free loopback port below the ephemeral range");
}

long read_before(int fd, std::chrono::steady_clock::time_point deadline, std::span<std::uint8_t> buf) {
  const auto left = std::chrono::ceil<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
  pollfd p{fd, POLLIN, 0};
  if (::poll(&p, 1, static_cast<int>(std::max<long>(left.count(), 0))) <= 0) return 0;
  const auto got = ::read(fd, buf.data(), buf.size());
  return got > 0 ? static_cast<long>(got) : -1;
}

bool wait_for_port(std::uint16_t port, std::chrono::milliseconds timeout) {
  return eventually([&] { return Socket::tcp(port).valid(); }, timeout);
}

Socket Socket::tcp(std::uint16_t port) {
  const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  auto addr = loopback(port);
  if (::connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) {
    ::close(fd);
    return Socket(-1);
  }
  return Socket(fd);
}

Socket Socket::tcp_from(const std::string& source, std::uint16_t port) {
  const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  auto from = loopback(0);
  auto addr = loopback(port);
  if (::inet_pton(AF_INET, source.c_str(), &from.sin_addr) != 1 ||
      ::bind(fd, reinterpret_cast<sockaddr*>(&from), sizeof from) != 0 ||
      ::connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) {
    ::close(fd);
    return Socket(-1);
  }
  return Socket(fd);
}

Socket Socket::unix_socket(const std::string& path) {
  const int fd = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
  sockaddr_un addr{};
  addr.sun_family = AF_UNIX;
  std::strncpy(addr.sun_path, path.c_str(), sizeof addr.sun_path - 1);
  if (::connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) {
    ::close(fd);
    return Socket(-1);
  }
  return Socket(fd);
}

Socket::Socket(Socket&& other) noexcept : fd_(other.fd_), buffered_(std::move(other.buffered_)) { other.fd_ = -1; }

Socket::~Socket() { close(); }

void Socket::close() {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
}

void Socket::send(const Bytes& bytes) const {
  std::size_t sent = 0;
  while (sent < bytes.size()) {
    const auto n = ::send(fd_, bytes.data() + sent, bytes.size() - sent, MSG_NOSIGNAL);
    if (n <= 0) return;
    sent += static_cast<std::size_t>(n);
  }
}

void Socket::send(const std::string& text) const { send(Bytes(text.begin(), text.end())); }

Bytes Socket::receive(std::size_t n, std::chrono::milliseconds timeout) const {
  Bytes out;
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  std::uint8_t buf[4096];
  while (out.size() < n) {
    const auto got = read_before(fd_, deadline, std::span(buf, std::min(sizeof buf, n - out.size())));
    if (got <= 0) break;
    out.insert(out.end(), buf, buf + got);
  }
  return out;
}

bool Socket::closed_by_peer(std::chrono::milliseconds timeout) const {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  std::uint8_t buf[512];
  while (true) {
    const auto got = read_before(fd_, deadline, buf);
    if (got < 0) return true;  // EOF or reset
    if (got == 0 && std::chrono::steady_clock::now() >= deadline) return false;
  }
}

std::optional<std::string> Socket::read_line(std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  std::uint8_t buf[4096];
  while (true) {
    const auto newline = buffered_.find('\n');
    if (newline != std::string::npos) {
      auto line = buffered_.substr(0, newline);
      buffered_.erase(0, newline + 1);
      return line;
    }
    const auto got = read_before(fd_, deadline, buf);
    if (got <= 0) return std::nullopt;
    buffered_.append(reinterpret_cast<const char*>(buf), static_cast<std::size_t>(got));
  }
}

bool Socket::wait_for_line(const std::string& line, std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (true) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) return false;
    const auto got = read_line(left);
    if (!got) return false;
    if (*got == line) return true;
  }
}

std::uint16_t Socket::local_port() const {
  sockaddr_in address{};
  socklen_t size = sizeof address;
  ::getsockname(fd_, reinterpret_cast<sockaddr*>(&address), &size);
  return ntohs(address.sin_port);
}

bool Socket::readable_now() const {
  pollfd p{fd_, POLLIN, 0};
  return ::poll(&p, 1, 0) == 1;
}

std::map<std::uint16_t, unsigned long> unread_by_server(std::uint16_t server_port) {
  std::map<std::uint16_t, unsigned long> unread;
  std::ifstream table("/proc/net/tcp");
  std::string line;
  std::getline(table, line);  // the heading
  while (std::getline(table, line)) {
    unsigned local_address = 0, local = 0, remote_address = 0, remote = 0, state = 0;
    unsigned long tx = 0, rx = 0;
    if (std::sscanf(line.c_str(), " %*d: %x:%x %x:%x %x %lx:%lx", &local_address, &local, &remote_address, &remote,
                    &state, &tx, &rx) == 7 &&
        local_address == 0x0100007F && local == server_port)
      unread[static_cast<std::uint16_t>(remote)] = rx;
  }
  return unread;
}

bool server_read_all(std::uint16_t server_port, const Socket& client) {
  const auto unread = unread_by_server(server_port);
  const auto found = unread.find(client.local_port());
  return found != unread.end() && found->second == 0;
}

}  // namespace unima::test_support
