#include "status/activity.hpp"

namespace unima::status {

Activity activity(std::optional<std::chrono::milliseconds> age, std::uint64_t frames, std::chrono::milliseconds lit) {
  return {age && *age <= lit, age ? std::optional(static_cast<std::int64_t>(age->count())) : std::nullopt, frames,
          static_cast<std::int64_t>(lit.count())};
}

}  // namespace unima::status
