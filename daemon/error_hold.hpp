#pragma once
// C+0x13 bit 15 "Modbus communication error": set on any fault, cleared after 2 s without
// one (SPEC §1, seed §8 "Error" LED).

#include <chrono>
#include <functional>

#include "daemon/asio.hpp"

namespace unima::daemon {

class ErrorHold {
 public:
  static constexpr std::chrono::seconds hold{2};

  ErrorHold(asio::io_context& io, std::function<void(bool)> set_error)
      : timer_(io), set_error_(std::move(set_error)) {}

  void fault() {
    set_error_(true);
    timer_.expires_after(hold);
    timer_.async_wait([this](const boost::system::error_code& ec) {
      if (!ec) set_error_(false);
    });
  }
  void cancel() { timer_.cancel(); }

 private:
  asio::steady_timer timer_;
  std::function<void(bool)> set_error_;
};

}  // namespace unima::daemon
