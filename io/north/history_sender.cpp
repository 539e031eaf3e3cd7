#include "io/north/history_sender.hpp"

#include <utility>

namespace unima::io {

void HistorySender::begin(MqttClient& client, std::string prefix) {
  client_ = &client;
  prefix_ = std::move(prefix);
  ++connection_;
  window_.restart();
  fill();
}

void HistorySender::end() {
  client_ = nullptr;
  ++connection_;
}

void HistorySender::acknowledged(int mid) {
  if (const auto delivered = window_.acknowledged(mid)) buffer_.acknowledge(*delivered);
  fill();
}

// Reads when half the window is free (or all of it): each read brings many entries, and
// the broker always has some in flight while the next ones are read.
void HistorySender::fill() {
  if (client_ == nullptr || reading_ || !client_->connected()) return;
  const auto room = window_.room();
  if (room == 0 || (window_.in_flight() > 0 && room < mqtt::HistoryWindow::max_unacknowledged / 2)) return;
  reading_ = true;
  buffer_.read(window_.sent_up_to(), room,
               [this, alive = alive_, connection = connection_, room](std::vector<mqtt::HistoryEntry> entries) {
                 if (!*alive) return;
                 reading_ = false;
                 if (connection != connection_ || client_ == nullptr) return fill();  // for a connection gone since
                 for (const auto& entry : entries) {
                   const auto mid = client_->publish_acknowledged(prefix_ + "/history/" + entry.bank, entry.document);
                   if (!mid) return;  // the connection went: the next one sends it again
                   window_.sent(entry.sequence, *mid);
                 }
                 if (entries.size() == room) fill();  // else that was all of it
               });
}

}  // namespace unima::io
