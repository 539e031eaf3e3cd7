#pragma once
// Undoes a step on destruction unless it was committed: how a reload puts back what it
// stopped when a later step fails (app/reload_plan.hpp), without a catch block per step.

#include <functional>
#include <utility>

namespace unima::app {

class Rollback {
 public:
  Rollback() = default;
  explicit Rollback(std::function<void()> undo) : undo_(std::move(undo)) {}
  Rollback(Rollback&& other) noexcept : undo_(std::exchange(other.undo_, nullptr)) {}
  Rollback& operator=(Rollback&& other) noexcept {
    if (this != &other) {
      run();
      undo_ = std::exchange(other.undo_, nullptr);
    }
    return *this;
  }
  Rollback(const Rollback&) = delete;
  Rollback& operator=(const Rollback&) = delete;
  ~Rollback() { run(); }

  /// The step stays: nothing is undone.
  void commit() { undo_ = nullptr; }

 private:
  void run() {
    if (auto undo = std::exchange(undo_, nullptr)) undo();
  }
  std::function<void()> undo_;
};

}  // namespace unima::app
