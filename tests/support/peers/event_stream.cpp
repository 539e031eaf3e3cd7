#include "tests/support/peers/event_stream.hpp"

#include <sys/socket.h>

#include "tests/support/eventually.hpp"

namespace unima::test_support {

EventStream::EventStream(std::uint16_t port, const std::string& target) : socket_(Socket::tcp(port)) {
  if (!socket_.valid()) return;
  // Short: each look for an event waits at most this long, and `eventually` looks again.
  timeval timeout{0, 200'000};
  ::setsockopt(socket_.fd(), SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof timeout);
  socket_.send("GET " + target + " HTTP/1.1\r\nHost: 127.0.0.1\r\nAccept: text/event-stream\r\n\r\n");
}

std::string EventStream::head(std::chrono::milliseconds within) {
  eventually([&] { return receive(), received_.find("\r\n\r\n") != std::string::npos; }, within);
  const auto end = received_.find("\r\n\r\n");
  if (end == std::string::npos) return {};
  auto header = received_.substr(0, end);
  received_.erase(0, end + 4);
  return header;
}

std::optional<nlohmann::json> EventStream::next(const std::string& name, std::chrono::milliseconds within) {
  std::optional<nlohmann::json> found;
  eventually([&] {
    receive();
    for (auto end = received_.find("\n\n"); end != std::string::npos; end = received_.find("\n\n")) {
      const auto block = received_.substr(0, end);
      received_.erase(0, end + 2);
      const auto data = block.find("\ndata: ");
      if (block.starts_with("event: " + name + "\n") && data != std::string::npos) {
        found = nlohmann::json::parse(block.substr(data + 7));
        return true;
      }
    }
    return false;
  }, within);
  return found;
}

void EventStream::receive() {
  char buffer[65536];
  const auto n = ::recv(socket_.fd(), buffer, sizeof buffer, 0);
  if (n > 0) received_.append(buffer, static_cast<std::size_t>(n));
}

}  // namespace unima::test_support
