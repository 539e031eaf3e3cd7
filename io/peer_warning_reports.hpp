#pragma once
// The timer that logs the counts of rate-limited peer warnings when a period ends
// (platform/peer_warnings): armed only while something is counted, so an idle daemon
// never wakes for it.

#include "io/lazy_deadline.hpp"
#include "platform/asio.hpp"
#include "platform/peer_warnings.hpp"

namespace unima::io {

class PeerWarningReports {
 public:
  explicit PeerWarningReports(const asio::any_io_executor& executor,
                              platform::PeerWarnings& warnings = platform::peer_warnings())
      : warnings_(warnings),
        timer_(executor, [this] { return warnings_.next_report(); },
               [this] {
                 warnings_.report(LazyDeadline::Clock::now());
                 timer_.watch();  // the next period, while peers are still counted
               }) {
    warnings_.on_period_opened([this] { timer_.watch(); });
  }
  ~PeerWarningReports() { warnings_.on_period_opened({}); }
  PeerWarningReports(const PeerWarningReports&) = delete;
  PeerWarningReports& operator=(const PeerWarningReports&) = delete;

 private:
  platform::PeerWarnings& warnings_;
  LazyDeadline timer_;
};

}  // namespace unima::io
