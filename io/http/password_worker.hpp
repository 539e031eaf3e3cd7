#pragma once
// Where the password hashes of `http.users` are computed (issue 29): on a thread of its
// own, never on the event loop that serves Modbus. The loop hands a password and a hash
// over and goes on; the verdict comes back to the loop as a posted handler.
//
// The thread is an io::CpuWorker of its own (one thread at nice 19; why, there). The queue in
// front of it is bounded by web::LoginLimits (its `checks`), so a login waits at most that
// many hashes.
//
// `done` runs on the loop, never after the worker is gone: the destructor waits for the
// hash being computed (a bcrypt of cost 12 takes ~0.25 s) and drops what is queued (their
// passwords overwritten), and a verdict posted before then is dropped. A check whose
// client went is abandoned (issue 43, finding 7): still queued, its hash is never computed;
// either way its `done` never runs.

#include <functional>
#include <memory>
#include <string>

#include "io/cpu_worker.hpp"
#include "platform/asio.hpp"

namespace unima::io {

class PasswordWorker {
 public:
  using Done = std::function<void(bool hash_matched)>;

  struct Check;
  /// A check handed over. It outlives the worker safely: abandon() after the worker is
  /// gone does nothing.
  class Ticket {
   public:
    Ticket() = default;
    explicit Ticket(std::shared_ptr<Check> check) : check_(std::move(check)) {}
    /// Its `done` will not run, and its hash is not computed unless it is already.
    void abandon();

   private:
    std::shared_ptr<Check> check_;
  };

  explicit PasswordWorker(asio::io_context& io);

  /// Computes web::hash_matches(password, hash) on the worker; `done` with its answer on
  /// the loop. The password is overwritten once used.
  Ticket check(std::string password, std::string hash, Done done);
  /// Checks handed over whose `done` has not run yet.
  std::size_t pending() const { return worker_.pending(); }

 private:
  CpuWorker worker_;
};

}  // namespace unima::io
