#pragma once
// The gateway's read cache (modbus.gateway.cache, SPEC §14, docs/gateway.md): the
// decisions only, from time points the caller passes in — no clock, no I/O.
//
// - A read (functions 1–4) equal to one answered within `window` — same unit, same PDU
//   bytes — gets that answer again without the line.
// - Only an answer with data is kept: an exception, a time-out or a bad frame never is
//   (the caller stores only the slave's good answers).
// - A write to a unit (any function but 1–4) empties that unit's cache.
// - Bounded, so a client scanning addresses cannot grow it without end: at most
//   `per_unit` answers for one unit and `total` in all; beyond, the oldest goes first.

#include <array>
#include <chrono>
#include <cstdint>
#include <deque>
#include <optional>
#include <span>
#include <vector>

namespace unima::master {

class GatewayCache {
 public:
  using Clock = std::chrono::steady_clock;
  using TimePoint = Clock::time_point;
  using Duration = Clock::duration;
  using Bytes = std::vector<std::uint8_t>;

  static constexpr std::size_t default_per_unit = 64;
  static constexpr std::size_t default_total = 1024;

  explicit GatewayCache(Duration window, std::size_t per_unit = default_per_unit, std::size_t total = default_total)
      : window_(window), per_unit_(per_unit), total_(total) {}

  /// Functions 1–4: what the cache may answer and keep.
  static bool is_read(std::span<const std::uint8_t> request_pdu);

  /// The answer PDU of an equal read answered within the window before `now`; nullopt
  /// when there is none (or `request_pdu` is no read).
  std::optional<Bytes> answer(std::uint8_t unit, std::span<const std::uint8_t> request_pdu, TimePoint now);
  /// The slave answered `request_pdu` with data (`answer_pdu`) at `now`: kept when it is a
  /// read and the answer no exception.
  void answered(std::uint8_t unit, std::span<const std::uint8_t> request_pdu, std::span<const std::uint8_t> answer_pdu,
                TimePoint now);
  /// A write goes to `unit` (from a client, or the master's own send): its answers go.
  void written(std::uint8_t unit);

  std::size_t size() const { return entries_.size(); }
  std::size_t size(std::uint8_t unit) const { return per_unit_count_[unit]; }

 private:
  struct Entry {
    std::uint8_t unit = 0;
    Bytes request;
    Bytes answer;
    TimePoint answered;
  };
  void forget_expired(TimePoint now);
  std::deque<Entry>::iterator erase(std::deque<Entry>::iterator it);

  Duration window_;
  std::size_t per_unit_;
  std::size_t total_;
  std::deque<Entry> entries_;  // oldest answer first
  std::array<std::size_t, 256> per_unit_count_{};
};

}  // namespace unima::master
