#pragma once
// Where the password hashes of `http.users` are computed (issue 29): on a thread of its
// own, never on the event loop that serves Modbus. The loop hands a password and a hash
// over and goes on; the verdict comes back to the loop as a posted handler.
//
// One thread, not a pool: the box has two cores and the loop needs one of them; a second
// hashing thread would only let guesses take the loop's core too. It runs at nice 19, so
// that where the two compete for a core the loop wins. The queue in front of it is
// bounded by web::LoginLimits (its `checks`), so a login waits at most that many hashes.
//
// `done` runs on the loop, never after the worker is gone: the destructor waits for the
// hash being computed (a bcrypt of cost 12 takes ~0.25 s) and drops what is queued, and a
// verdict posted before then finds the worker gone and is dropped.

#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "platform/asio.hpp"

namespace unima::io {

class PasswordWorker {
 public:
  using Done = std::function<void(bool hash_matched)>;

  explicit PasswordWorker(asio::io_context& io);
  ~PasswordWorker();
  PasswordWorker(const PasswordWorker&) = delete;
  PasswordWorker& operator=(const PasswordWorker&) = delete;

  /// Computes web::hash_matches(password, hash) on the worker; `done` with its answer on
  /// the loop. The password is overwritten once used.
  void check(std::string password, std::string hash, Done done);
  /// Checks handed over whose `done` has not run yet.
  std::size_t pending() const;

 private:
  struct Shared;
  std::shared_ptr<Shared> shared_;
};

}  // namespace unima::io
