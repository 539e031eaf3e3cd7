#pragma once
// The lifetime rule of io/'s handlers (docs/architecture.md, "Lifetimes of handlers"), for
// an object owned by another through a unique_ptr — a port, an acceptor — whose queued
// handlers may run after it was closed or destroyed (a reload replaces ports while their
// handlers wait in the loop). A handler captures a token and touches the object only
// when `alive(token) && guard.current(token)`: the object still exists, and has not been
// closed since.
// Objects that live by their own I/O (a TCP connection, a feed session, the master's
// links) hold themselves in their handlers with shared_from_this instead, as Asio's
// examples do.

#include <memory>

namespace unima::io {

class HandlerGuard {
 public:
  struct Token {
    std::weak_ptr<int> alive;
    unsigned generation = 0;
  };

  Token token() const { return {alive_, generation_}; }
  /// False once the object is gone. Checked first: it reads only the token.
  static bool alive(const Token& token) { return !token.alive.expired(); }
  /// Whether nothing invalidated the token since; only while alive(token).
  bool current(const Token& token) const { return token.generation == generation_; }
  /// Handlers queued before this see their tokens invalid (the object was closed).
  void invalidate() { ++generation_; }

 private:
  std::shared_ptr<int> alive_ = std::make_shared<int>(0);
  unsigned generation_ = 0;
};

}  // namespace unima::io
