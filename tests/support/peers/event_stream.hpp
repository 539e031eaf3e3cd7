#pragma once
// The front page's listener of /api/events (SPEC §13): an EventSource as a browser opens
// it, reading the server-sent events as they come, so that a test sees which events the
// bridge sends, in which order, and that it sends none while nothing changes.

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "tests/support/loopback.hpp"

namespace unima::test_support {

class EventStream {
 public:
  /// Connects to 127.0.0.1:port and asks for `target` ("/api/events?fn=3").
  EventStream(std::uint16_t port, const std::string& target);

  /// The header, once it came.
  std::string head(std::chrono::milliseconds within = std::chrono::milliseconds(5000));
  /// The data of the next event named `name` (others before it are skipped), or nullopt.
  std::optional<nlohmann::json> next(const std::string& name, std::chrono::milliseconds within = std::chrono::milliseconds(5000));

 private:
  void receive();
  Socket socket_;
  std::string received_;
};

}  // namespace unima::test_support
