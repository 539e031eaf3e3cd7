#include "io/mqtt/history_sender.hpp"

#include <algorithm>
#include <iterator>
#include <utility>

namespace unima::io {

void HistorySender::begin(MqttClient& client, std::string prefix) {
  client_ = &client;
  prefix_ = std::move(prefix);
  ++connection_;
  window_.restart();
  ready_.clear();  // the new connection starts after what was delivered
  exhausted_ = false;
  fill();
}

void HistorySender::end() {
  client_ = nullptr;
  ++connection_;
  ready_.clear();
}

void HistorySender::acknowledged(int mid) {
  if (const auto delivered = window_.acknowledged(mid)) buffer_.acknowledge(*delivered);
  fill();
}

// Each acknowledgement frees room that entries already read fill at once, and the next
// entries are read while the window is still full: the broker never waits for the
// buffer's thread. (Read only when half the window was free, the window emptied during
// each read — woken, the thread may wait a scheduler slice, some ms on a busy host — and a
// local mosquitto got 7,700 messages/s instead of the 16,000 it takes with 100 in flight.)
void HistorySender::fill() {
  if (client_ == nullptr || !client_->connected()) return;
  while (window_.room() > 0 && !ready_.empty()) {
    const auto& entry = ready_.front();
    const auto mid = client_->publish_acknowledged(prefix_ + "/history/" + entry.bank, entry.document);
    if (!mid) return;  // the connection went: the next one sends it again
    window_.sent(entry.sequence, *mid);
    ready_.pop_front();
  }
  if (reading_ || exhausted_ || ready_.size() >= read_ahead / 2) return;
  reading_ = true;
  const auto after = ready_.empty() ? window_.sent_up_to() : ready_.back().sequence;
  buffer_.read(after, read_ahead - ready_.size(),
               [this, alive = alive_, connection = connection_](std::vector<mqtt::HistoryEntry> entries) {
                 if (!*alive) return;
                 reading_ = false;
                 if (connection != connection_) return fill();  // for a connection gone since
                 exhausted_ = entries.empty();
                 std::move(entries.begin(), entries.end(), std::back_inserter(ready_));
                 fill();
               });
}

}  // namespace unima::io
