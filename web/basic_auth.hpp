#pragma once
// Who may open the front page and the HTTP API when it is reached from beyond loopback
// (SPEC §13, `http.users`): HTTP basic authentication against a file of
// "name:password-hash" lines, the format of Apache's htpasswd, with the hashes glibc's
// crypt(3) reads — SHA-512 ("$6$", `openssl passwd -6`), SHA-256 ("$5$"), bcrypt
// ("$2b$"/"$2y$", `htpasswd -B`) and yescrypt ("$y$", `mkpasswd`).
//
// A hash costs milliseconds by design, and it is computed on the event loop that serves
// Modbus: credentials that passed are remembered (so a browser's every request does not
// pay again), and the checks that do compute are limited to a few a second, beyond which
// the answer is 429 — someone guessing passwords slows down, the loop does not.

#include <chrono>
#include <cstdint>
#include <list>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>

namespace unima::web {

/// "dXNlcjpwYXNz" -> "user:pass"; nullopt when it is not base64.
std::optional<std::string> decode_base64(std::string_view text);

class BasicAuth {
 public:
  using Clock = std::chrono::steady_clock;
  static constexpr unsigned checks_per_second = 5;
  static constexpr unsigned check_burst = 10;
  static constexpr std::size_t remembered = 64;

  /// Reads the users file; throws std::runtime_error naming the key, the file and the line
  /// ("http.users /etc/…/http-users:3: 'bob' has no password hash ...").
  static BasicAuth load(const std::string& path);
  /// From the file's text, `origin` naming it in errors.
  static BasicAuth parse(std::string_view text, const std::string& origin);

  enum class Verdict : std::uint8_t { allowed, refused, too_many };
  struct Result {
    Verdict verdict = Verdict::refused;
    std::string user;  // who, when allowed
  };
  /// Judges a request's Authorization header (empty when it has none).
  Result check(std::string_view authorization, Clock::time_point now);

  std::size_t users() const { return hashes_.size(); }

 private:
  bool take_token(Clock::time_point now);
  void remember(const std::string& header, const std::string& user);

  std::map<std::string, std::string, std::less<>> hashes_;  // name -> crypt(3) hash
  std::unordered_map<std::string, std::string> passed_;      // Authorization header -> user
  std::list<std::string> passed_order_;                      // oldest first, to forget
  double tokens_ = check_burst;
  Clock::time_point refilled_{};
};

}  // namespace unima::web
