#pragma once
// A telegram's owner (SPEC §6): every telegram a transport receives comes here, and
// here it is routed into its D_N or S_N bank (TelegramRouter; the store refuses one that
// runs past the bank's end), recorded (`unimabus.record`), counted, and its device is
// marked heard (Presence), on-line in the store (C+0x13) and off-line again when it falls
// silent. Across a reload the new config's intake takes the old one over. Pure: the
// caller passes the time, arms one timer at next_expiry() and logs what changed.

#include <array>
#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "banks/register_store.hpp"
#include "unimabus/presence.hpp"
#include "unimabus/telegram.hpp"
#include "unimabus/telegram_router.hpp"

namespace unima::unimabus {

/// Where telegrams are recorded (io::TelegramRecorder for `unimabus.record`).
class TelegramRecording {
 public:
  virtual ~TelegramRecording() = default;
  virtual void record(const Telegram& telegram, std::chrono::steady_clock::time_point now) = 0;
};

class TelegramIntake {
 public:
  using Clock = Presence::Clock;

  struct Counts {
    std::uint64_t received = 0;  // every telegram, whatever became of it (the UnimaBUS LED)
    std::array<std::uint64_t, banks::bank_count> taken{};  // by the bank that took them
    std::uint64_t ignored = 0;  // for no configured D_N or S_N: another device's
    std::uint64_t refused = 0;  // answered with an error (ambiguous, past a bank's end)
  };

  /// A bank that came on-line or went off-line, for the caller to log.
  struct PresenceChange {
    banks::BankId bank;
    bool online;
    bool operator==(const PresenceChange&) const = default;
  };

  struct Taken {
    std::string error;  // for the sender; empty when taken or ignored
    std::vector<PresenceChange> changes;
  };

  TelegramIntake(std::vector<Route> routes, banks::RegisterStore& store, Clock::duration offline_after)
      : router_(std::move(routes), store), store_(store), presence_(offline_after) {}

  void set_recording(TelegramRecording* recording) { recording_ = recording; }

  Taken take(const Telegram& telegram, Clock::time_point now);
  /// The banks silent longer than `offline_after` at `now`, set off-line in the store.
  std::vector<PresenceChange> expire(Clock::time_point now);
  /// When the next on-line bank goes off-line if nothing is heard.
  std::optional<Clock::time_point> next_expiry() const { return presence_.next_expiry(); }

  /// For a reload, on the new config's intake (its store has already taken the old
  /// store's values, banks::RegisterStore::take_state_from): a bank the new store kept
  /// stays on-line, heard at `now`; every other bank is off-line (those that were on-line
  /// are returned). The counts and the last telegram's time carry over.
  std::vector<PresenceChange> take_over(const TelegramIntake& old, Clock::time_point now);

  const Counts& counts() const { return counts_; }
  std::optional<Clock::time_point> last_telegram() const { return last_telegram_; }

 private:
  TelegramRouter router_;
  banks::RegisterStore& store_;
  Presence presence_;
  TelegramRecording* recording_ = nullptr;
  Counts counts_;
  std::optional<Clock::time_point> last_telegram_;
};

}  // namespace unima::unimabus
