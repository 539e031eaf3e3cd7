#include "modbus/rtu/rtu_timing.hpp"

#include <cstdint>

namespace unima::modbus {

namespace {
// Above this rate the specification fixes the gaps instead of counting characters.
constexpr unsigned fixed_timing_above_baud = 19200;

std::chrono::microseconds characters(std::uint64_t tenths, unsigned bits, unsigned baud) {
  // tenths of characters × bits ÷ baud, in µs, rounded up.
  const std::uint64_t numerator = tenths * bits * 1'000'000ULL;
  const std::uint64_t denominator = 10ULL * baud;
  return std::chrono::microseconds((numerator + denominator - 1) / denominator);
}
}  // namespace

RtuTiming rtu_timing(unsigned baud, bool parity, unsigned stop_bits) {
  const unsigned bits = 1 + 8 + (parity ? 1 : 0) + stop_bits;
  RtuTiming timing;
  timing.baud = baud;
  timing.bits_per_character = bits;
  timing.character = characters(10, bits, baud);
  if (baud > fixed_timing_above_baud) {
    timing.frame_gap = std::chrono::microseconds(1750);
    timing.reply_delay = std::chrono::microseconds(1250);
  } else {
    timing.frame_gap = characters(35, bits, baud);
    timing.reply_delay = characters(25, bits, baud);
  }
  return timing;
}

}  // namespace unima::modbus
