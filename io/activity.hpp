#pragma once
// An LED of the front panel as the status document shows it (SPEC §8): lit for a moment
// after each frame it shows, how long ago the last one was and how many there were. The
// page blinks an LED when its count moves (it samples the panel every 250 ms, longer than
// a blink), `unima-bridge status` shows whether it is lit now.

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <optional>

#include <nlohmann/json.hpp>

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

/// {"active": lit now, "last_ms_ago", "frames": how many it has shown, "lit_ms"}.
inline nlohmann::json activity(std::optional<std::chrono::milliseconds> age, std::uint64_t frames,
                               std::chrono::milliseconds lit) {
  nlohmann::json j;
  j["active"] = age && *age <= lit;
  j["last_ms_ago"] = age ? nlohmann::json(age->count()) : nlohmann::json(nullptr);
  j["frames"] = frames;
  j["lit_ms"] = lit.count();
  return j;
}

}  // namespace unima::io
