#include "io/north/password_worker.hpp"

#include <sys/resource.h>
#include <unistd.h>

#include <condition_variable>
#include <deque>
#include <map>
#include <mutex>
#include <thread>
#include <utility>

#include "web/basic_auth.hpp"

namespace unima::io {

struct PasswordWorker::Shared {
  struct Job {
    std::uint64_t id = 0;
    std::string password;
    std::string hash;
  };

  explicit Shared(asio::io_context& io) : io(io) {}

  asio::io_context& io;

  // The loop's side: the callbacks never leave the loop's thread (what they hold — an
  // HTTP connection — is the loop's to destroy).
  std::map<std::uint64_t, Done> waiting;
  std::uint64_t next_id = 0;

  // Under the mutex.
  std::mutex mutex;
  std::condition_variable wake;
  std::deque<Job> queued;
  bool stopping = false;

  std::thread thread;

  void run(const std::weak_ptr<Shared>& self);
  void finished(std::uint64_t id, bool matched) {
    const auto found = waiting.find(id);
    if (found == waiting.end()) return;
    auto done = std::move(found->second);
    waiting.erase(found);
    done(matched);
  }
};

void PasswordWorker::Shared::run(const std::weak_ptr<Shared>& self) {
  // The lowest priority for this thread alone (Linux's nice is per thread): where it and
  // the loop want the same core, the loop runs and the hash waits. Lowering needs no
  // privilege; if refused, the hash runs at the loop's priority, as before.
  (void)::setpriority(PRIO_PROCESS, static_cast<id_t>(::gettid()), 19);
  while (true) {
    Job job;
    {
      std::unique_lock lock(mutex);
      wake.wait(lock, [&] { return stopping || !queued.empty(); });
      if (stopping) return;
      job = std::move(queued.front());
      queued.pop_front();
    }
    const bool matched = web::hash_matches(job.password, job.hash);
    web::forget_password(job.password);
    asio::post(io, [self, id = job.id, matched] {
      if (const auto shared = self.lock()) shared->finished(id, matched);
    });
  }
}

PasswordWorker::PasswordWorker(asio::io_context& io) : shared_(std::make_shared<Shared>(io)) {
  shared_->thread = std::thread([shared = shared_.get(), weak = std::weak_ptr<Shared>(shared_)] { shared->run(weak); });
}

PasswordWorker::~PasswordWorker() {
  {
    const std::lock_guard lock(shared_->mutex);
    shared_->stopping = true;
    for (auto& job : shared_->queued) web::forget_password(job.password);
    shared_->queued.clear();
  }
  shared_->wake.notify_one();
  shared_->thread.join();
}

void PasswordWorker::check(std::string password, std::string hash, Done done) {
  const auto id = shared_->next_id++;
  shared_->waiting.emplace(id, std::move(done));
  {
    const std::lock_guard lock(shared_->mutex);
    shared_->queued.push_back({id, std::move(password), std::move(hash)});
  }
  shared_->wake.notify_one();
}

std::size_t PasswordWorker::pending() const { return shared_->waiting.size(); }

}  // namespace unima::io
