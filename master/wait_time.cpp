#include "master/wait_time.hpp"

#include <algorithm>

namespace unima::master {

// The caller's clock readings come from one steady clock, but a request queued and taken in
// the same instant may read as a few nanoseconds "before": never a negative wait.
void WaitTime::took_line(Duration waited) {
  waited = std::max(waited, Duration::zero());
  ++count_;
  sum_ += waited;
  last_ = waited;
  max_ = std::max(max_, waited);
}

}  // namespace unima::master
