#include "sparkplug/rebirth_pacing.hpp"

namespace unima::sparkplug {

RebirthPacing::Verdict RebirthPacing::asked(Clock::time_point now) {
  if (due_) {
    ++coalesced_;
    return Verdict::joined;
  }
  if (!last_ || now - *last_ >= min_interval) {
    last_ = now;
    return Verdict::now;
  }
  ++coalesced_;
  due_ = true;
  due_at_ = *last_ + min_interval;
  return Verdict::later;
}

void RebirthPacing::done(Clock::time_point now) {
  due_ = false;
  last_ = now;
}

}  // namespace unima::sparkplug
