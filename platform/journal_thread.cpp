#include "platform/journal_thread.hpp"

#include <utility>

namespace unima::platform {

JournalThread::~JournalThread() { stop(); }

void JournalThread::start(Turn turn, std::optional<Clock::time_point> first) {
  thread_ = std::thread([this, turn = std::move(turn), first] { run(turn, first); });
}

void JournalThread::hand_over(const std::function<void()>& put, bool urgent) {
  bool notify = false;
  {
    const std::lock_guard lock(mutex_);
    put();
    if (urgent) {
      urgent_ = true;
      notify = std::exchange(sleeping_, false);
    }
  }
  if (notify) wake_.notify_one();
}

void JournalThread::take(const std::function<void()>& take) {
  const std::lock_guard lock(mutex_);
  take();
}

void JournalThread::stop() {
  if (!thread_.joinable()) return;
  {
    const std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_one();
  thread_.join();
}

void JournalThread::run(Turn turn, std::optional<Clock::time_point> due) {
  while (true) {
    bool last = false;
    {
      std::unique_lock lock(mutex_);
      const auto woken = [&] { return urgent_ || stopping_; };
      sleeping_ = true;
      if (due) wake_.wait_until(lock, *due, woken);
      else wake_.wait(lock, woken);
      sleeping_ = false;
      urgent_ = false;
      last = stopping_;
    }
    due = turn(last);
    if (last) return;
  }
}

}  // namespace unima::platform
