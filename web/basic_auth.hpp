#pragma once
// Who may open the front page and the HTTP API when it is reached from beyond loopback
// (SPEC §13, `http.users`): HTTP basic authentication against a file of
// "name:password-hash" lines, the format of Apache's htpasswd, with the hashes glibc's
// crypt(3) reads — SHA-512 ("$6$", `openssl passwd -6`), SHA-256 ("$5$"), bcrypt
// ("$2b$"/"$2y$", `htpasswd -B`) and yescrypt ("$y$", `mkpasswd`).
//
// A hash costs milliseconds by design (bcrypt at cost 12: a quarter of a second), so it is
// never computed on the event loop that serves Modbus. Judging a request is split in two:
// judge() answers on the loop what needs no hash — an Authorization header that passed
// before (remembered, so a browser's every request does not pay again), or one that is no
// name and password at all — and otherwise names the PasswordCheck to make;
// hash_matches() computes it on a worker (io/http/password_worker); remember() keeps the
// header once it passed. How many checks may run, and for whom, is web/login_limits'.

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

/// A hash to compute, and what its answer means.
struct PasswordCheck {
  std::string authorization;  // the header, remembered when it passes
  std::string user;
  std::string password;
  std::string hash;  // the user's; another user's when the name is unknown (the same cost)
  bool known_user = false;

  bool passed(bool hash_matched) const { return known_user && hash_matched; }
};

/// crypt(3) of `password` with the salt and cost of `hash` is `hash` (compared in a time that
/// does not depend on where they differ). Reentrant (crypt_rn): for a worker thread.
bool hash_matches(const std::string& password, const std::string& hash);

/// Overwrites a password before its memory is given back.
void forget_password(std::string& password);

class BasicAuth {
 public:
  static constexpr std::size_t remembered = 64;

  /// Reads the users file; throws std::runtime_error naming the key's position in the config
  /// (`key_origin`, "bridge.yaml:41:10", when given), the file and the line ("bridge.yaml:41:10:
  /// http.users /etc/…/http-users:3: 'bob' has no password hash ..."): `check` and the
  /// daemon say the same.
  static BasicAuth load(const std::string& path, const std::string& key_origin = {});
  /// From the file's text, `origin` naming it in errors.
  static BasicAuth parse(std::string_view text, const std::string& origin);

  enum class Verdict : std::uint8_t { allowed, refused, check };
  struct Judgement {
    Verdict verdict = Verdict::refused;
    std::string user;                  // who, when allowed
    std::optional<PasswordCheck> check;  // what to compute, when `check`
  };
  /// Judges a request's Authorization header (empty when it has none) as far as it can
  /// without a hash.
  Judgement judge(std::string_view authorization) const;
  /// A check that passed: the same header is allowed without a hash from now on (the
  /// `remembered` latest).
  void remember(const PasswordCheck& passed);

  std::size_t users() const { return hashes_.size(); }
  /// Whether the file lists `name` (remote_config.http names users of it: check/).
  bool has_user(std::string_view name) const { return hashes_.find(name) != hashes_.end(); }

 private:
  std::map<std::string, std::string, std::less<>> hashes_;  // name -> crypt(3) hash
  std::unordered_map<std::string, std::string> passed_;      // Authorization header -> user
  std::list<std::string> passed_order_;                      // oldest first, to forget
};

}  // namespace unima::web
