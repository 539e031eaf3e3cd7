#include "mqtt/history_window.hpp"

#include <algorithm>

namespace unima::mqtt {

void HistoryWindow::restart() {
  in_flight_.clear();
  sent_up_to_ = delivered_;
}

void HistoryWindow::sent(std::uint64_t sequence, int mid) {
  in_flight_.push_back({sequence, mid});
  sent_up_to_ = std::max(sent_up_to_, sequence);
}

std::optional<std::uint64_t> HistoryWindow::acknowledged(int mid) {
  const auto found = std::find_if(in_flight_.begin(), in_flight_.end(), [&](const InFlight& f) { return f.mid == mid && !f.acknowledged; });
  if (found == in_flight_.end()) return std::nullopt;  // of an earlier connection's handle, or not ours
  found->acknowledged = true;
  ++acknowledged_total_;
  const auto before = delivered_;
  while (!in_flight_.empty() && in_flight_.front().acknowledged) {
    delivered_ = in_flight_.front().sequence;
    in_flight_.pop_front();
  }
  if (delivered_ == before) return std::nullopt;
  return delivered_;
}

}  // namespace unima::mqtt
