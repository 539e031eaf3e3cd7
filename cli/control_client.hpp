#pragma once
// The CLI's side of the daemon's control socket (io/control_socket.hpp): one connection,
// an optional request line, one answer read to its end.

#include <chrono>
#include <optional>
#include <string>

namespace unima::cli {

struct ControlAnswer {
  std::optional<std::string> text;  // none: `error` says why
  std::string error;
};

/// Connects to `path`, sends `request` (one line, the newline added) when given, and reads
/// the answer until the daemon closes, within `timeout`.
ControlAnswer ask_control(const std::string& path, const std::optional<std::string>& request,
                          std::chrono::milliseconds timeout);

/// The socket the commands ask: --socket, else --config's status.socket, else the default.
/// Throws (std::exception) when --config's file cannot be read.
std::string control_socket_path(const std::string& socket, const std::string& config_path);

}  // namespace unima::cli
