#pragma once
// A browser's or Prometheus' request to the bridge's HTTP server (SPEC §13), written by
// hand on a plain socket: the test sends exactly the bytes it means (a wrong method, a
// header too large) and sees the reply as it came, which no HTTP library would let it.

#include <chrono>
#include <cstdint>
#include <string>

namespace unima::test_support {

struct HttpReply {
  int status = 0;    // 0: no reply, or not HTTP
  std::string head;  // the status line and the headers, without the blank line
  std::string body;
};

/// Sends `request` as it is to 127.0.0.1:port (from `source` when given, e.g. 127.0.0.2 to
/// be another host) and reads the reply to the end (Connection: close), each read waiting
/// at most `patience` (more for a reply that waits behind slow password hashes).
HttpReply http_exchange(std::uint16_t port, const std::string& request, const std::string& source = {},
                        std::chrono::seconds patience = std::chrono::seconds(5));

/// The reply in `all` (what a server sent until it closed); status 0 when it is no HTTP reply.
HttpReply parse_http_reply(const std::string& all);

/// GET `path`, the connection closed after the reply.
HttpReply http_get(std::uint16_t port, const std::string& path);

}  // namespace unima::test_support
