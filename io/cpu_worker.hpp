#pragma once
// Where CPU-heavy work of the daemon runs (issue 29): on a thread of its own, never on the
// event loop that serves Modbus. The loop hands a job over and goes on; the job's
// completion comes back to the loop as a posted handler. Its users: the password checks of
// `http.users` (io/http/password_worker), the TLS handshakes of the Modbus/TCP Security
// port (io/modbus/tls_connection), and the Sparkplug bdSeq file's write and fdatasync
// before each CONNECT (io/mqtt/sparkplug_service), each with an instance of its own.
//
// One thread, not a pool: the gateways have two cores and the loop needs one of them; a
// second worker thread would only let a flood of logins or handshakes take the loop's core
// too. It runs at nice 19, so that where the two compete for a core the loop wins. The
// queue is bounded: a job beyond `capacity` is refused, and the caller says what that means.
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

  CpuWorker(asio::io_context& io, std::size_t capacity);
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
