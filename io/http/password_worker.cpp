#include "io/http/password_worker.hpp"

#include <limits>
#include <memory>
#include <utility>

#include "web/basic_auth.hpp"

namespace unima::io {

namespace {

// Shared by the job (on the worker) and its completion (on the loop); whichever lets go
// last overwrites the password, so a check dropped unrun forgets it too.
struct Check {
  std::string password;
  std::string hash;
  bool matched = false;
  ~Check() { web::forget_password(password); }
};

}  // namespace

// The callers bound the checks in flight (web::LoginLimits), so the worker's own bound is
// never what refuses one.
PasswordWorker::PasswordWorker(asio::io_context& io) : worker_(io, std::numeric_limits<std::size_t>::max()) {}

void PasswordWorker::check(std::string password, std::string hash, Done done) {
  auto check = std::make_shared<Check>();
  check->password = std::move(password);
  check->hash = std::move(hash);
  worker_.submit(
      [check] {
        check->matched = web::hash_matches(check->password, check->hash);
        web::forget_password(check->password);
      },
      [check, done = std::move(done)] { done(check->matched); });
}

}  // namespace unima::io
