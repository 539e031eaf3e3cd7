#include "tests/support/peers/http_exchange.hpp"

#include <sys/socket.h>

#include "tests/support/loopback.hpp"

namespace unima::test_support {

HttpReply parse_http_reply(const std::string& all) {
  HttpReply reply;
  const auto end = all.find("\r\n\r\n");
  if (end == std::string::npos || all.size() < 12) return reply;
  reply.head = all.substr(0, end);
  reply.body = all.substr(end + 4);
  reply.status = std::stoi(all.substr(9, 3));
  return reply;
}

HttpReply http_exchange(std::uint16_t port, const std::string& request, const std::string& source, std::chrono::seconds patience) {
  HttpReply reply;
  auto socket = source.empty() ? Socket::tcp(port) : Socket::tcp_from(source, port);
  if (!socket.valid()) return reply;
  timeval timeout{static_cast<time_t>(patience.count()), 0};
  ::setsockopt(socket.fd(), SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof timeout);
  socket.send(request);
  std::string all;
  char buffer[4096];
  for (ssize_t n; (n = ::recv(socket.fd(), buffer, sizeof buffer, 0)) > 0;) all.append(buffer, static_cast<std::size_t>(n));
  return parse_http_reply(all);
}

HttpReply http_get(std::uint16_t port, const std::string& path) {
  return http_exchange(port, "GET " + path + " HTTP/1.1\r\nHost: 127.0.0.1\r\nConnection: close\r\n\r\n");
}

}  // namespace unima::test_support
