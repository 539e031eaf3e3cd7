#include "cli/control_client.hpp"

#include <poll.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include <fmt/format.h>

#include "config/config.hpp"

namespace unima::cli {

namespace {

bool send_all(int fd, std::string_view bytes) {
  while (!bytes.empty()) {
    const auto n = ::send(fd, bytes.data(), bytes.size(), MSG_NOSIGNAL);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    bytes.remove_prefix(static_cast<std::size_t>(n));
  }
  return true;
}

}  // namespace

ControlAnswer ask_control(const std::string& path, const std::optional<std::string>& request,
                          std::chrono::milliseconds timeout) {
  ControlAnswer answer;
  const int fd = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  std::strncpy(address.sun_path, path.c_str(), sizeof address.sun_path - 1);
  if (::connect(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0) {
    answer.error = fmt::format("cannot reach the daemon on {}: {}", path, std::strerror(errno));
    ::close(fd);
    return answer;
  }
  if (request && !send_all(fd, *request + "\n")) {
    answer.error = fmt::format("cannot send to the daemon on {}: {}", path, std::strerror(errno));
    ::close(fd);
    return answer;
  }
  std::string text;
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (true) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
    pollfd p{fd, POLLIN, 0};
    if (left.count() <= 0 || ::poll(&p, 1, static_cast<int>(left.count())) <= 0) {
      answer.error = fmt::format("the daemon on {} did not answer within {} s", path,
                                 std::chrono::duration_cast<std::chrono::seconds>(timeout).count());
      ::close(fd);
      return answer;
    }
    char buffer[8192];
    const auto n = ::read(fd, buffer, sizeof buffer);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    text.append(buffer, static_cast<std::size_t>(n));
  }
  ::close(fd);
  answer.text = std::move(text);
  return answer;
}

std::string control_socket_path(const std::string& socket, const std::string& config_path) {
  if (!socket.empty()) return socket;
  if (!config_path.empty()) return config::load_file(config_path).status.socket;
  return config::StatusConfig{}.socket;
}

}  // namespace unima::cli
