#include "monitor/write_outage.hpp"

namespace unima::monitor {

bool WriteOutage::failed(Clock::time_point now) {
  last_failure_ = now;
  ++failed_writes_;
  if (failing_) return false;
  failing_ = true;
  first_failure_ = now;
  failed_writes_ = 1;
  return true;
}

std::optional<WriteOutage::Recovery> WriteOutage::succeeded(Clock::time_point now) {
  if (!failing_ || now - last_failure_ < settle_) return std::nullopt;
  failing_ = false;
  return Recovery{last_failure_ - first_failure_, failed_writes_};
}

}  // namespace unima::monitor
