#pragma once
// Where CPU-heavy work of the daemon runs (issue 29): on a thread of its own, never on the
// event loop that serves Modbus. The loop hands a job over and goes on; the job's
// completion comes back to the loop as a posted handler. Its users: the password checks of
// `http.users` (io/http/password_worker), the TLS handshakes of the Modbus/TCP Security
// port (io/modbus/tls_connection), the Sparkplug bdSeq file's write and fdatasync before
// each CONNECT (io/mqtt/sparkplug_service), and a config from afar's load, check and keep
// (app/remote_config_coordinator), each with an instance of its own.
//
// One thread, not a pool: the gateways have two cores and the loop needs one of them; a
// second worker thread would only let a flood of logins or handshakes take the loop's core
// too. It runs below the loop's priority, so that where the two compete for a core the loop
// wins (Priority). The queue is bounded: a job beyond `capacity` is refused, and the caller
// says what that means.
//
// A job runs on the worker and is destroyed there: it must hold nothing that may only die on
// the loop (a connection is kept alive by its completion, which never leaves the loop's
// thread). A completion runs on the loop, never after the worker is gone: the destructor
// drops what is queued (neither the job nor its completion runs), waits for the job being
// run, and a completion posted before then finds the worker gone and is dropped.

#include <cstddef>
#include <functional>
#include <memory>

#include "platform/asio.hpp"

namespace unima::io {

class CpuWorker {
 public:
  using Job = std::function<void()>;
  using Done = std::function<void()>;

  /// How the worker's thread stands against the loop and the box's other programs.
  enum class Priority {
    /// nice 19: work an attacker may ask for at will and nobody waits on in real time
    /// (password hashes, a file's sync): it gets what the box leaves over.
    background,
    /// nice 5: work a real client waits on against a deadline (TLS handshakes, issue 43):
    /// the loop still wins three to one on a shared core, but a box busy with other
    /// programs leaves it a share instead of the crumbs nice 19 gets.
    beside_the_loop,
  };

  CpuWorker(asio::io_context& io, std::size_t capacity, Priority priority = Priority::background);
  ~CpuWorker();
  CpuWorker(const CpuWorker&) = delete;
  CpuWorker& operator=(const CpuWorker&) = delete;

  /// Runs `job` on the worker, then `done` on the loop. False (and neither runs) when
  /// `capacity` jobs are queued or running already. Called on the loop only.
  bool submit(Job job, Done done);
  /// Jobs handed over whose `done` has not run yet.
  std::size_t pending() const;

 private:
  struct Shared;
  std::shared_ptr<Shared> shared_;
};

}  // namespace unima::io
