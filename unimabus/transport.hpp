#pragma once
// The bridge's way to UnimaBUS (SPEC §6). The wire protocol is not public, so every
// transport (sim, feed, replay) delivers telegrams and takes what the bridge publishes.

#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>

#include "banks/bank_id.hpp"
#include "unimabus/telegram.hpp"

namespace unima::unimabus {

/// Applies a telegram; returns "" or why it was rejected (for the sender to see).
using TelegramHandler = std::function<std::string(const Telegram&)>;

class Transport {
 public:
  virtual ~Transport() = default;
  virtual void start() = 0;
  virtual void stop() = 0;
  /// A value the bridge publishes changed or was written: W, X, C+0x00..0x12.
  virtual void publish(banks::BankId bank, std::uint16_t offset, std::uint16_t value) = 0;
  /// Connected drivers, for a transport that has them (the feed); nullopt otherwise.
  virtual std::optional<std::size_t> clients() const { return std::nullopt; }
};

}  // namespace unima::unimabus
