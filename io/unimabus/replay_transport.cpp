#include "io/unimabus/replay_transport.hpp"

#include <spdlog/spdlog.h>

namespace unima::io {

namespace {

// Telegrams due at one instant are applied this many per turn of the loop, so that a
// recording with thousands at one time never holds Modbus clients up.
constexpr int telegrams_per_turn = 256;

}  // namespace

ReplayTransport::ReplayTransport(asio::io_context& io, std::shared_ptr<const unimabus::Recording> recording,
                                 double speed, bool loop, unimabus::TelegramHandler on_telegram)
    : timer_(io),
      recording_(std::move(recording)),
      schedule_(*recording_, speed, loop),
      on_telegram_(std::move(on_telegram)) {}

void ReplayTransport::start() {
  spdlog::info("unimabus: replaying {} ({} telegrams over {:.3f} s)", recording_->origin, recording_->entries.size(),
               recording_->duration());
  start_ = std::chrono::steady_clock::now();
  arm();
}

void ReplayTransport::stop() {
  stopped_ = true;
  timer_.cancel();
}

void ReplayTransport::arm() {
  const auto due = schedule_.next_due();
  if (!due) {
    spdlog::info("unimabus: the recording {} is over; its devices fall silent", recording_->origin);
    return;
  }
  timer_.expires_at(start_ + std::chrono::duration_cast<std::chrono::steady_clock::duration>(*due));
  timer_.async_wait([this](const boost::system::error_code& ec) {
    if (!ec && !stopped_) play();
  });
}

void ReplayTransport::play() {
  const auto elapsed = std::chrono::steady_clock::now() - start_;
  for (int n = 0; n < telegrams_per_turn; ++n) {
    const auto* entry = schedule_.take_due(elapsed);
    if (!entry) break;
    const auto refusal = on_telegram_(entry->telegram);
    // A recording refused once is refused at every pass: the first says why, the rest count.
    if (!refusal.empty() && refused_++ == 0)
      spdlog::warn("unimabus replay: {}:{}: {} (further refusals are counted, not logged)", recording_->origin,
                   entry->line, refusal);
  }
  arm();
}

}  // namespace unima::io
