#pragma once
// The `replay` UnimaBUS transport (SPEC §6): plays a recording made by `record` (or
// written by hand) into the bridge, each telegram at its time divided by the speed, so a
// SCADA can be commissioned in the office against the plant's own telegrams. One timer,
// armed for the next telegram only.

#include <chrono>
#include <memory>

#include "platform/asio.hpp"
#include "unimabus/recording.hpp"
#include "unimabus/transport.hpp"

namespace unima::io {

class ReplayTransport final : public unimabus::Transport {
 public:
  ReplayTransport(asio::io_context& io, std::shared_ptr<const unimabus::Recording> recording, double speed, bool loop,
                  unimabus::TelegramHandler on_telegram);

  void start() override;
  void stop() override;
  /// A recording has nobody to read what the bridge publishes; it is only counted.
  void publish(banks::BankId, std::uint16_t, std::uint16_t) override { ++published_; }

 private:
  void play();
  void arm();

  asio::steady_timer timer_;
  std::shared_ptr<const unimabus::Recording> recording_;  // before schedule_, which refers to it
  unimabus::ReplaySchedule schedule_;
  unimabus::TelegramHandler on_telegram_;
  std::chrono::steady_clock::time_point start_;
  std::uint64_t refused_ = 0;
  std::uint64_t published_ = 0;
  bool stopped_ = false;
};

}  // namespace unima::io
