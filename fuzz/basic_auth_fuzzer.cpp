// Fuzz target: what a browser or a scraper sends the HTTP server to log in (SPEC §13,
// `http.users`): the Authorization header, judged by web::BasicAuth against a users file —
// the part of a request the daemon parses itself (Beast parses the rest). The users file
// is the operator's, but a bad one must fail as a config error, never otherwise.
//
// Input: the users file's text up to the first byte 0x00; after it, the Authorization
// header. Without a 0x00, the whole input is the header and the users file is the one below.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>

#include "fuzz/fuzz_check.hpp"
#include "web/basic_auth.hpp"

namespace {

using namespace unima;

constexpr std::string_view origin = "http.users fuzz";
// `openssl passwd -6 'tech pass'`: judging computes no hash, so its cost does not matter.
constexpr std::string_view default_users =
    "technician:$6$rounds=5000$Vbkm1V2IU1p3LXN7$ykIgySEG0r0.bMfhqUlZNhXcmKAUwM9Wl4Zqk2N5l0Ch6vY4dm6G2dU7TGmHdmSYXPj3e0DqS7u4Ey9AGF0Ge1\n";

bool starts_with_basic(std::string_view header) {
  constexpr std::string_view scheme = "basic ";
  if (header.size() < scheme.size()) return false;
  for (std::size_t i = 0; i < scheme.size(); ++i)
    if (static_cast<char>(std::tolower(static_cast<unsigned char>(header[i]))) != scheme[i]) return false;
  return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto text = std::string_view(reinterpret_cast<const char*>(data), size);
  const auto split = text.find('\0');
  const auto users_text = split == std::string_view::npos ? default_users : text.substr(0, split);
  const auto header = split == std::string_view::npos ? text : text.substr(split + 1);

  std::optional<web::BasicAuth> users;
  try {
    users = web::BasicAuth::parse(users_text, std::string(origin));
  } catch (const std::runtime_error& e) {
    // A config error names the key and the file, and the line where there is one.
    FUZZ_CHECK(std::string_view(e.what()).starts_with(origin));
    return 0;
  }
  FUZZ_CHECK(users->users() > 0);

  const auto judged = users->judge(header);
  FUZZ_CHECK((judged.verdict == web::BasicAuth::Verdict::check) == judged.check.has_value());
  FUZZ_CHECK(judged.verdict != web::BasicAuth::Verdict::allowed);  // nothing has passed yet
  if (!judged.check) return 0;
  const auto& check = *judged.check;
  // A check is asked only for "Basic <base64 of name:password>", and carries exactly that.
  FUZZ_CHECK(check.authorization == header);
  FUZZ_CHECK(starts_with_basic(header));
  const auto decoded = web::decode_base64(header.substr(6));
  FUZZ_CHECK(decoded.has_value());
  FUZZ_CHECK(*decoded == check.user + ":" + check.password);
  FUZZ_CHECK(check.user.find(':') == std::string::npos);
  FUZZ_CHECK(!check.hash.empty());
  // Once it passed, the same header is let in without a hash, as the same user.
  if (check.known_user) {
    users->remember(check);
    const auto again = users->judge(header);
    FUZZ_CHECK(again.verdict == web::BasicAuth::Verdict::allowed);
    FUZZ_CHECK(again.user == check.user);
  }
  return 0;
}
