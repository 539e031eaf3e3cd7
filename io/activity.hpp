#pragma once
// An LED of the front panel as the status document shows it: "active" while the last
// frame is recent, and how long ago it was.

#include <algorithm>
#include <chrono>
#include <optional>

#include <nlohmann/json.hpp>

namespace unima::io {

// An LED that blinks on traffic reads "active" while the last frame is this recent.
inline constexpr auto activity_window = std::chrono::seconds(1);

/// How long ago, never negative (the wall clock may have been set back since).
template <typename Clock>
std::optional<std::chrono::milliseconds> age(const std::optional<typename Clock::time_point>& last) {
  if (!last) return std::nullopt;
  return std::max(std::chrono::milliseconds(0), std::chrono::duration_cast<std::chrono::milliseconds>(Clock::now() - *last));
}

inline nlohmann::json activity(std::optional<std::chrono::milliseconds> age) {
  nlohmann::json j;
  j["active"] = age && *age <= activity_window;
  j["last_ms_ago"] = age ? nlohmann::json(age->count()) : nlohmann::json(nullptr);
  return j;
}

}  // namespace unima::io
