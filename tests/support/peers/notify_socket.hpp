#pragma once
// systemd's end of the sd_notify(3) protocol: the datagram socket a service manager binds
// and names in NOTIFY_SOCKET, so that a test reads READY, RELOADING, STOPPING, STATUS and
// WATCHDOG as systemd would, without running the daemon under systemd.

#include <chrono>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace unima::test_support {

/// The service manager's end of NOTIFY_SOCKET: a bound datagram socket.
class NotifySocket {
 public:
  explicit NotifySocket(const std::filesystem::path& path);
  ~NotifySocket();
  NotifySocket(const NotifySocket&) = delete;
  NotifySocket& operator=(const NotifySocket&) = delete;

  std::string environment() const { return "NOTIFY_SOCKET=" + path_.string(); }

  /// Reads messages until one carries the assignment `line` (e.g. "READY=1"); returns that
  /// whole message, or nullopt at the deadline. Every message read is kept in `seen()`.
  std::optional<std::string> wait_for(const std::string& line, std::chrono::milliseconds timeout = std::chrono::milliseconds(5000));
  static bool carries(const std::string& message, const std::string& line);
  const std::vector<std::string>& seen() const { return seen_; }

 private:
  std::filesystem::path path_;
  int fd_ = -1;
  std::vector<std::string> seen_;
};

}  // namespace unima::test_support
