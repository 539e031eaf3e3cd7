#pragma once
// The history in flight after a reconnect (SPEC §15): at most 100 entries published and not
// yet acknowledged by the broker (QoS 1 PUBACK), so that a reconnect never floods it; the
// history counts as delivered up to the entry before the oldest one still unacknowledged,
// whatever order the acknowledgements come in. A new connection starts again after what
// was delivered: what was in flight on the lost one is sent again (at least once, never
// lost). Pure: the client's message ids and the entries' sequences are handed in.

#include <cstddef>
#include <cstdint>
#include <deque>
#include <optional>

namespace unima::mqtt {

class HistoryWindow {
 public:
  static constexpr std::size_t max_unacknowledged = 100;

  /// `delivered`: the last sequence the journal says was acknowledged.
  explicit HistoryWindow(std::uint64_t delivered = 0) : delivered_(delivered), sent_up_to_(delivered) {}

  /// A new connection: nothing is in flight; sending goes on after what was delivered.
  void restart();
  /// How many more entries may be published now.
  std::size_t room() const { return max_unacknowledged - in_flight_.size(); }
  std::size_t in_flight() const { return in_flight_.size(); }
  /// Entries after this sequence are the next to send.
  std::uint64_t sent_up_to() const { return sent_up_to_; }
  std::uint64_t delivered() const { return delivered_; }
  /// Entries the broker acknowledged since the start (each once, on whichever connection).
  std::uint64_t acknowledged_total() const { return acknowledged_total_; }

  /// Entry `sequence` went out as message `mid`.
  void sent(std::uint64_t sequence, int mid);
  /// The broker acknowledged message `mid`: the new delivered sequence when it moved.
  std::optional<std::uint64_t> acknowledged(int mid);

 private:
  struct InFlight {
    std::uint64_t sequence;
    int mid;
    bool acknowledged = false;
  };
  std::uint64_t delivered_;
  std::uint64_t sent_up_to_;
  std::uint64_t acknowledged_total_ = 0;
  std::deque<InFlight> in_flight_;  // in the order sent
};

}  // namespace unima::mqtt
