#include "io/cpu_worker.hpp"

#include <sys/resource.h>
#include <unistd.h>

#include <cerrno>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <map>
#include <mutex>
#include <thread>
#include <utility>

namespace unima::io {

struct CpuWorker::Shared {
  struct Queued {
    std::uint64_t id = 0;
    Job job;
  };

  Shared(asio::io_context& io, std::size_t capacity, int nice) : io(io), capacity(capacity), nice(nice) {}

  asio::io_context& io;
  const std::size_t capacity;
  const int nice;

  // The loop's side: the completions never leave the loop's thread (what they hold — a
  // connection — is the loop's to destroy).
  std::map<std::uint64_t, Done> waiting;
  std::uint64_t next_id = 0;

  // Under the mutex.
  std::mutex mutex;
  std::condition_variable wake;
  std::deque<Queued> queued;
  bool stopping = false;

  std::thread thread;

  void run(const std::weak_ptr<Shared>& self);
  void finished(std::uint64_t id) {
    const auto found = waiting.find(id);
    if (found == waiting.end()) return;
    auto done = std::move(found->second);
    waiting.erase(found);
    done();
  }
};

void CpuWorker::Shared::run(const std::weak_ptr<Shared>& self) {
  // A lower priority for this thread alone (Linux's nice is per thread): where it and the
  // loop want the same core, the loop runs first. Lowering needs no privilege; if refused,
  // the job runs at the loop's priority. Never raised above the process's own.
  errno = 0;
  const int own = ::getpriority(PRIO_PROCESS, static_cast<id_t>(::gettid()));
  if (errno == 0 && own < nice) (void)::setpriority(PRIO_PROCESS, static_cast<id_t>(::gettid()), nice);
  while (true) {
    Queued next;
    {
      std::unique_lock lock(mutex);
      wake.wait(lock, [&] { return stopping || !queued.empty(); });
      if (stopping) return;
      next = std::move(queued.front());
      queued.pop_front();
    }
    next.job();
    next.job = nullptr;  // its captures die here, before the loop may see the completion
    asio::post(io, [self, id = next.id] {
      if (const auto shared = self.lock()) shared->finished(id);
    });
  }
}

CpuWorker::CpuWorker(asio::io_context& io, std::size_t capacity, Priority priority)
    : shared_(std::make_shared<Shared>(io, capacity, priority == Priority::background ? 19 : 5)) {
  shared_->thread = std::thread([shared = shared_.get(), weak = std::weak_ptr<Shared>(shared_)] { shared->run(weak); });
}

CpuWorker::~CpuWorker() {
  std::deque<Shared::Queued> dropped;
  {
    const std::lock_guard lock(shared_->mutex);
    shared_->stopping = true;
    dropped.swap(shared_->queued);
  }
  shared_->wake.notify_one();
  shared_->thread.join();
  dropped.clear();
  // The completions (and what they hold) die with shared_, here on the loop's thread.
}

bool CpuWorker::submit(Job job, Done done) {
  if (shared_->waiting.size() >= shared_->capacity) return false;
  const auto id = shared_->next_id++;
  shared_->waiting.emplace(id, std::move(done));
  {
    const std::lock_guard lock(shared_->mutex);
    shared_->queued.push_back({id, std::move(job)});
  }
  shared_->wake.notify_one();
  return true;
}

std::size_t CpuWorker::pending() const { return shared_->waiting.size(); }

}  // namespace unima::io
