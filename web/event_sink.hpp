#pragma once
// The open end of a server-sent event stream, as the HTTP server hands it to whoever
// feeds it (web/live_view). No Asio here, so that the feeding side is testable without it.

#include <cstddef>
#include <string_view>

namespace unima::web {

/// The open end of a server-sent event stream (text/event-stream, the page's live
/// updates). Sending queues; a client that lets more than `max_queued_bytes` pile up is
/// too slow for live values and is closed (SPEC §10's rule for the feed, here too).
class EventSink {
 public:
  static constexpr std::size_t max_queued_bytes = 1024 * 1024;
  virtual ~EventSink() = default;
  /// Queues `events` (whole "event: …\ndata: …\n\n" blocks); false once the stream is closed.
  virtual bool send(std::string_view events) = 0;
  virtual bool closed() const = 0;
};

}  // namespace unima::web
