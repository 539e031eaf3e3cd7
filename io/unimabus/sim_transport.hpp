#pragma once
// The `sim` UnimaBUS transport: a timer that feeds the simulator's telegrams to the
// bridge, for the demo and for trying a config without a plant.

#include <chrono>

#include "platform/asio.hpp"
#include "unimabus/sim_generator.hpp"
#include "unimabus/transport.hpp"

namespace unima::io {

class SimTransport final : public unimabus::Transport {
 public:
  SimTransport(asio::io_context& io, unimabus::SimGenerator generator, std::chrono::milliseconds period,
               unimabus::TelegramHandler on_telegram)
      : timer_(io), generator_(std::move(generator)), period_(period), on_telegram_(std::move(on_telegram)) {}

  void start() override;
  void stop() override;
  /// The simulated plant has nobody to read what the bridge publishes; it is only counted.
  void publish(banks::BankId, std::uint16_t, std::uint16_t) override { ++published_; }

 private:
  void tick();

  asio::steady_timer timer_;
  unimabus::SimGenerator generator_;
  std::chrono::milliseconds period_;
  unimabus::TelegramHandler on_telegram_;
  std::chrono::steady_clock::time_point next_;
  std::uint64_t published_ = 0;
  bool stopped_ = false;
};

}  // namespace unima::io
