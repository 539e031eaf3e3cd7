#include "io/http/password_worker.hpp"

#include <atomic>
#include <limits>
#include <memory>
#include <utility>

#include "web/basic_auth.hpp"

namespace unima::io {

// Shared by the job (on the worker), its completion and its ticket (on the loop); whichever
// lets go last overwrites the password, so a check dropped unrun forgets it too.
struct PasswordWorker::Check {
  std::string password;
  std::string hash;
  bool matched = false;
  std::atomic<bool> abandoned = false;  // set on the loop, read on the worker too
  ~Check() { web::forget_password(password); }
};

void PasswordWorker::Ticket::abandon() {
  if (check_) check_->abandoned = true;
}

// The callers bound the checks in flight (web::LoginLimits), so the worker's own bound is
// never what refuses one.
PasswordWorker::PasswordWorker(asio::io_context& io) : worker_(io, std::numeric_limits<std::size_t>::max()) {}

PasswordWorker::Ticket PasswordWorker::check(std::string password, std::string hash, Done done) {
  auto check = std::make_shared<Check>();
  check->password = std::move(password);
  check->hash = std::move(hash);
  worker_.submit(
      [check] {
        if (!check->abandoned) check->matched = web::hash_matches(check->password, check->hash);
        web::forget_password(check->password);
      },
      [check, done = std::move(done)] {
        if (!check->abandoned) done(check->matched);
      });
  return Ticket(check);
}

}  // namespace unima::io
