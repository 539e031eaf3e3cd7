#pragma once
// C+0x13 bit 15 "Modbus communication error": set on any fault, cleared after 2 s without
// one (SPEC §1, seed §8 "Error" LED).

#include <chrono>
#include <functional>

#include "platform/asio.hpp"

namespace unima::io {

class ErrorHold {
 public:
  static constexpr std::chrono::seconds hold{2};
  using Clock = std::chrono::steady_clock;

  ErrorHold(asio::io_context& io, std::function<void(bool)> set_error)
      : timer_(io), set_error_(std::move(set_error)) {}

  // A client that keeps asking for a missing register faults on every request; the timer
  // is armed once and not per fault (that would cost a timerfd call each time): on expiry
  // it looks at the last fault and waits for the remainder of the hold.
  void fault() {
    last_fault_ = Clock::now();
    set_error_(true);
    if (!armed_) arm(hold);
  }
  void cancel() {
    armed_ = false;
    timer_.cancel();
  }

 private:
  void arm(Clock::duration after) {
    armed_ = true;
    timer_.expires_after(after);
    timer_.async_wait([this](const boost::system::error_code& ec) {
      if (ec) return;  // cancelled: cancel() has cleared armed_
      armed_ = false;
      const auto quiet = Clock::now() - last_fault_;
      if (quiet >= hold) return set_error_(false);
      arm(hold - quiet);
    });
  }

  asio::steady_timer timer_;
  std::function<void(bool)> set_error_;
  Clock::time_point last_fault_;
  bool armed_ = false;
};

}  // namespace unima::io
