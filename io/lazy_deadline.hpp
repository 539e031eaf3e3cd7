#pragma once
// A timer for a deadline that mostly moves later: the last fault plus the error hold, a
// client's last request plus the idle time-out, the framer's silence, a device's next
// expiry. Arming an Asio timer costs a timerfd call, so it is armed only when nothing is
// armed; when it fires it asks for the deadline again and, if that has moved, waits for the
// rest. Every timer of the daemon whose deadline moves with traffic goes through here.
//
// Lifetime (io/handler_guard): the handler holds a token and touches nothing once the
// object is gone or the wait was cancelled, even when the timer had already fired and its
// handler was waiting in the loop. So the owner may cancel or destroy it at any time on
// the loop's thread.

#include <chrono>
#include <functional>
#include <optional>

#include "io/handler_guard.hpp"
#include "platform/asio.hpp"

namespace unima::io {

class LazyDeadline {
 public:
  using Clock = std::chrono::steady_clock;
  /// When it is due now; nullopt when there is nothing to wait for.
  using DeadlineFn = std::function<std::optional<Clock::time_point>()>;

  LazyDeadline(const asio::any_io_executor& executor, DeadlineFn deadline, std::function<void()> on_due)
      : timer_(executor), deadline_(std::move(deadline)), on_due_(std::move(on_due)) {}
  LazyDeadline(const LazyDeadline&) = delete;
  LazyDeadline& operator=(const LazyDeadline&) = delete;
  ~LazyDeadline() { cancel(); }

  /// Arms the timer at the current deadline unless it is armed already (it then fires
  /// early at worst, and waits again).
  void watch() {
    if (armed_) return;
    const auto due = deadline_();
    if (!due) return;
    armed_ = true;
    timer_.expires_at(*due);
    timer_.async_wait([this, token = guard_.token()](const boost::system::error_code& ec) {
      if (ec || !HandlerGuard::alive(token) || !guard_.current(token)) return;
      armed_ = false;
      const auto due = deadline_();
      if (!due) return;
      if (Clock::now() < *due) return watch();
      on_due_();
    });
  }

  void cancel() {
    armed_ = false;
    guard_.invalidate();
    timer_.cancel();
  }

 private:
  asio::steady_timer timer_;
  DeadlineFn deadline_;
  std::function<void()> on_due_;
  HandlerGuard guard_;
  bool armed_ = false;
};

}  // namespace unima::io
