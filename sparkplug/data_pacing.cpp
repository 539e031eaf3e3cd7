#include "sparkplug/data_pacing.hpp"

namespace unima::sparkplug {

std::optional<DataPacing::Clock::time_point> DataPacing::changed(Clock::time_point now) {
  if (due_) return std::nullopt;
  due_ = true;
  if (!last_look_ || now - *last_look_ >= interval) return now;
  return *last_look_ + interval;
}

void DataPacing::looked(Clock::time_point now) {
  last_look_ = now;
  due_ = false;
}

DataPacing::Clock::time_point DataPacing::retry(Clock::time_point now) {
  due_ = true;
  return now + interval;
}

}  // namespace unima::sparkplug
