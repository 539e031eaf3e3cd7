#include "io/unimabus/sim_transport.hpp"

#include <spdlog/spdlog.h>

namespace unima::io {

void SimTransport::start() {
  spdlog::info("unimabus: simulated plant, a telegram round every {} ms", period_.count());
  next_ = std::chrono::steady_clock::now();
  tick();
}

void SimTransport::stop() {
  stopped_ = true;
  timer_.cancel();
}

void SimTransport::tick() {
  for (const auto& telegram : generator_.tick()) {
    const auto refusal = on_telegram_(telegram);
    if (!refusal.empty()) spdlog::warn("unimabus sim: {}", refusal);
  }
  next_ += period_;  // from the schedule, not from now, so rounds do not drift
  timer_.expires_at(next_);
  timer_.async_wait([this](const boost::system::error_code& ec) {
    if (!ec && !stopped_) tick();
  });
}

}  // namespace unima::io
