#pragma once
// Who hears that the banks changed (SPEC §12, §13: values go north on the leading edge).
// The register store raises its signal at the first change after it was armed
// (banks::RegisterStore::set_change_signal); this posts one wake-up to the loop and there
// — after what else the loop had ready, so that the telegrams of one read make one
// wake-up — arms the signal again and tells each listener. A listener compares
// banks::RegisterStore::changes itself to know which banks changed. Without listeners the
// store is never armed, and a telegram costs nothing more. The wall-clock time of the
// signal — the first change of a round, so the arrival of what one read brought — is what
// the values changed in that round were measured at (SPEC §21, report/measurement_times).

#include <chrono>
#include <functional>
#include <vector>

#include "banks/register_store.hpp"
#include "platform/asio.hpp"

namespace unima::io {

class StoreChanges {
 public:
  explicit StoreChanges(asio::io_context& io) : io_(io) {}
  StoreChanges(const StoreChanges&) = delete;
  StoreChanges& operator=(const StoreChanges&) = delete;

  /// Listens to `store`: the running banks', again after each reload swapped them.
  void attach(banks::RegisterStore& store) {
    store_ = &store;
    store.set_change_signal([this] {
      changed_at_ = std::chrono::system_clock::now();
      asio::post(io_, [this] { ring(); });
    });
    if (!listeners_.empty()) store.arm_change_signal();
  }
  /// `listener` runs on the loop after changes, at most once per wake-up. For as long as
  /// the loop runs: a service listens from its construction.
  void listen(std::function<void()> listener) {
    listeners_.push_back(std::move(listener));
    if (store_) store_->arm_change_signal();
  }
  /// When the latest round of changes began (before any: when this was made, the start).
  std::chrono::system_clock::time_point changed_at() const { return changed_at_; }

 private:
  void ring() {
    if (store_) store_->arm_change_signal();
    for (const auto& listener : listeners_) listener();
  }

  asio::io_context& io_;
  banks::RegisterStore* store_ = nullptr;
  std::vector<std::function<void()>> listeners_;
  std::chrono::system_clock::time_point changed_at_ = std::chrono::system_clock::now();
};

}  // namespace unima::io
