#pragma once
// C+0x13 bit 15 "Modbus communication error": set on any fault, cleared after 2 s without
// one (SPEC §1, seed §8 "Error" LED).

#include <chrono>
#include <functional>

#include "io/lazy_deadline.hpp"

namespace unima::io {

class ErrorHold {
 public:
  static constexpr std::chrono::seconds hold{2};
  using Clock = LazyDeadline::Clock;

  // A client that keeps asking for a missing register faults on every request: the timer
  // is armed once, not per fault (LazyDeadline).
  ErrorHold(asio::io_context& io, std::function<void(bool)> set_error)
      : set_error_(std::move(set_error)),
        clear_(io.get_executor(), [this] { return std::optional(last_fault_ + hold); }, [this] { set_error_(false); }) {}

  void fault() {
    last_fault_ = Clock::now();
    set_error_(true);
    clear_.watch();
  }
  void cancel() { clear_.cancel(); }

 private:
  std::function<void(bool)> set_error_;
  Clock::time_point last_fault_;
  LazyDeadline clear_;
};

}  // namespace unima::io
