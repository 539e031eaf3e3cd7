#pragma once
// The front panel's LEDs as the services see them (SPEC §8): how long each stays lit and
// how long ago its last frame was, for the status document's status::Activity
// (status/activity.hpp).

#include <algorithm>
#include <chrono>
#include <optional>

namespace unima::io {

// As on the hardware (seed 004 §2): the Modbus LED after each frame the bridge sends, the
// UnimaBUS LED after each telegram received.
inline constexpr auto modbus_led_lit = std::chrono::milliseconds(100);
inline constexpr auto unimabus_led_lit = std::chrono::milliseconds(50);

/// How long ago, never negative (the wall clock may have been set back since).
template <typename Clock>
std::optional<std::chrono::milliseconds> age(const std::optional<typename Clock::time_point>& last) {
  if (!last) return std::nullopt;
  return std::max(std::chrono::milliseconds(0), std::chrono::duration_cast<std::chrono::milliseconds>(Clock::now() - *last));
}

}  // namespace unima::io
