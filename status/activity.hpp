#pragma once
// An LED of the front panel as the status document shows it (SPEC §8): lit for a moment
// after each frame it shows, how long ago the last one was and how many there were — the
// Modbus LED ("modbus", the monitor's) and the UnimaBUS LED (in "unimabus"). The page
// blinks an LED when its count moves (it samples the panel every 250 ms, longer than a
// blink), `unima-bridge status` shows whether it is lit now.

#include <chrono>
#include <cstdint>
#include <optional>

#include <nlohmann/json.hpp>

#include "status/json_optional.hpp"

namespace unima::status {

struct Activity {
  bool active = false;                      // lit now
  std::optional<std::int64_t> last_ms_ago;  // none: no frame yet
  std::uint64_t frames = 0;                 // how many it has shown
  std::int64_t lit_ms = 0;                  // how long it stays lit after one
};
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE_WITH_DEFAULT(Activity, active, last_ms_ago, frames, lit_ms)

/// The LED that stays `lit` after each frame, its last frame `age` ago (none: no frame yet).
Activity activity(std::optional<std::chrono::milliseconds> age, std::uint64_t frames, std::chrono::milliseconds lit);

}  // namespace unima::status
