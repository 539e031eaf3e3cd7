#pragma once
// Character timing of a Modbus RTU line (Modbus over Serial Line V1.02 §2.5.1.1, seed 004
// §4.1). Pure arithmetic: the ports and the framer take their durations from here.

#include <chrono>

namespace unima::modbus {

struct RtuTiming {
  unsigned baud = 0;
  /// Start bit, 8 data bits, the parity bit if any, stop bits.
  unsigned bits_per_character = 0;
  /// One character on the wire.
  std::chrono::microseconds character{0};
  /// t3.5: the silence that ends a frame; fixed at 1750 µs above 19200 baud.
  std::chrono::microseconds frame_gap{0};
  /// The least wait between a request's last byte and the reply's first (seed §4.1:
  /// 2.5 characters); fixed at 1250 µs above 19200 baud, in proportion to t3.5.
  std::chrono::microseconds reply_delay{0};
  bool operator==(const RtuTiming&) const = default;
};

/// Rounded up to whole microseconds, so that a wait is never shorter than the rule.
RtuTiming rtu_timing(unsigned baud, bool parity, unsigned stop_bits);

}  // namespace unima::modbus
