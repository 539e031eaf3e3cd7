#pragma once
// The thread that writes and fdatasyncs a journal on the disk — the state file's
// (io/state_file) and the MQTT history buffer's (io/mqtt/history_buffer) — so that the
// loop never waits for the disk: fdatasync blocks for as long as the disk takes, longer
// on a busy or failing one, and the loop serves Modbus.
//
// The loop hands work over under the thread's lock (held for a push, never for the disk),
// and says whether it is urgent: an urgent hand-over wakes the thread at once, any other
// waits for the thread's next turn. Each turn runs outside the lock; it takes what was
// handed over (take), writes and syncs it, posts its results to the loop, and says when
// the next turn is due by itself (nullopt: only when woken). Work handed over during a
// turn is taken by the next, which starts as soon as that one returns: the disk is never
// idle while work waits, and all the work of one turn shares its sync (group commit).
// Stopping runs one last turn, told so, that writes and syncs whatever is left: a clean
// stop loses nothing.

#include <chrono>
#include <condition_variable>
#include <functional>
#include <mutex>
#include <optional>
#include <thread>

namespace unima::platform {

class JournalThread {
 public:
  using Clock = std::chrono::steady_clock;
  /// One turn; `last`: the thread stops after it. Returns when the next turn is due
  /// without being woken (nullopt: only when woken).
  using Turn = std::function<std::optional<Clock::time_point>(bool last)>;

  JournalThread() = default;
  /// Stops (stop()) if it runs.
  ~JournalThread();
  JournalThread(const JournalThread&) = delete;
  JournalThread& operator=(const JournalThread&) = delete;

  /// Starts the thread; its first turn is due at `first` (nullopt: when woken).
  void start(Turn turn, std::optional<Clock::time_point> first = std::nullopt);
  /// The loop's side: runs `put` under the lock; `urgent` wakes the thread at once.
  void hand_over(const std::function<void()>& put, bool urgent);
  /// The thread's side, within a turn: runs `take` under the lock.
  void take(const std::function<void()>& take);
  /// Runs the last turn and joins the thread.
  void stop();

 private:
  void run(Turn turn, std::optional<Clock::time_point> due);

  std::mutex mutex_;
  std::condition_variable wake_;
  bool urgent_ = false;    // work the thread must take at once
  bool sleeping_ = false;  // the thread waits for wake_: an urgent hand-over notifies it
  bool stopping_ = false;
  std::thread thread_;
};

}  // namespace unima::platform
