// io::CpuWorker in-process: a job runs on the worker's thread at the priority its user
// asked for (issue 43: the TLS handshakes' worker beside the loop, the password hashes'
// in the background), and its completion comes back on the loop.

#include <gtest/gtest.h>
#include <sys/resource.h>
#include <unistd.h>

#include <cerrno>
#include <thread>

#include "io/cpu_worker.hpp"

namespace unima::io {
namespace {

// The nice of the thread that ran a job, seen by the completion on the loop.
struct Observed {
  int nice = -100;
  std::thread::id job_thread;
  std::thread::id completion_thread;
};

Observed run_one(CpuWorker::Priority priority) {
  asio::io_context io;
  auto keep_running = asio::make_work_guard(io);  // until the completion comes back
  Observed seen;
  {
    CpuWorker worker(io, 1, priority);
    const bool taken = worker.submit(
        [&seen] {
          errno = 0;
          seen.nice = ::getpriority(PRIO_PROCESS, static_cast<id_t>(::gettid()));
          seen.job_thread = std::this_thread::get_id();
        },
        [&seen, &keep_running] {
          seen.completion_thread = std::this_thread::get_id();
          keep_running.reset();
        });
    EXPECT_TRUE(taken);
    EXPECT_FALSE(worker.submit([] {}, [] {}));  // capacity 1: the first is still pending
    io.run_for(std::chrono::seconds(10));
    EXPECT_EQ(worker.pending(), 0u);
  }
  return seen;
}

int own_nice() {
  errno = 0;
  return ::getpriority(PRIO_PROCESS, static_cast<id_t>(::gettid()));
}

TEST(CpuWorker, TheHandshakesWorkerRunsBesideTheLoopAndThePasswordsInTheBackground) {
  const auto beside = run_one(CpuWorker::Priority::beside_the_loop);
  const auto background = run_one(CpuWorker::Priority::background);
  // Never raised above the process's own: a test run under nice keeps its nice.
  EXPECT_EQ(beside.nice, std::max(5, own_nice()));
  EXPECT_EQ(background.nice, std::max(19, own_nice()));
  for (const auto& seen : {beside, background}) {
    EXPECT_NE(seen.job_thread, std::this_thread::get_id());
    EXPECT_EQ(seen.completion_thread, std::this_thread::get_id());
  }
}

}  // namespace
}  // namespace unima::io
