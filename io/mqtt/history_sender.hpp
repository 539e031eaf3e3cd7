#pragma once
// The history after a reconnect (SPEC §15): once a connection's live documents are out, the
// buffer's entries go oldest first on <prefix>/history/<bank>, QoS 1, not retained, at most
// mqtt::HistoryWindow::max_unacknowledged unacknowledged at once; each one the broker
// acknowledges is marked delivered in the buffer. A connection that drops mid-history
// leaves the rest, and what was in flight, to the next one (at least once: a subscriber may
// get an entry twice, never miss one). On the loop; the buffer reads on its own thread.

#include <cstddef>
#include <cstdint>
#include <deque>
#include <memory>
#include <string>

#include "io/mqtt/history_buffer.hpp"
#include "io/mqtt/mqtt_client.hpp"
#include "mqtt/history_window.hpp"

namespace unima::io {

class HistorySender {
 public:
  explicit HistorySender(HistoryBuffer& buffer) : buffer_(buffer), window_(buffer.delivered_at_start()) {}
  ~HistorySender() { *alive_ = false; }
  HistorySender(const HistorySender&) = delete;
  HistorySender& operator=(const HistorySender&) = delete;

  /// `client` has just published the live documents of its new connection: the history
  /// follows on it. `client` must outlive the sending, or end() be called first.
  void begin(MqttClient& client, std::string prefix);
  /// No more on the client given to begin().
  void end();
  /// The client's on_acknowledged: message `mid` reached the broker.
  void acknowledged(int mid);
  /// History messages the broker acknowledged since the start.
  std::uint64_t sent() const { return window_.acknowledged_total(); }

 private:
  // Entries held read ahead of the window: a read is asked for when fewer than half are
  // left, so the next ones are here before the window has sent these (io/mqtt/history_sender.cpp).
  static constexpr std::size_t read_ahead = 4 * mqtt::HistoryWindow::max_unacknowledged;
  void fill();

  HistoryBuffer& buffer_;
  mqtt::HistoryWindow window_;
  MqttClient* client_ = nullptr;
  std::string prefix_;
  std::uint64_t connection_ = 0;  // which begin() a read belongs to
  std::deque<mqtt::HistoryEntry> ready_;  // read, not yet published, oldest first
  bool reading_ = false;
  bool exhausted_ = false;  // the last read found nothing more (the buffer grows only while disconnected)
  std::shared_ptr<bool> alive_ = std::make_shared<bool>(true);
};

}  // namespace unima::io
