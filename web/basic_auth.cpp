#include "web/basic_auth.hpp"

#include <crypt.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <memory>
#include <sstream>
#include <stdexcept>

#include <fmt/format.h>

namespace unima::web {

namespace {

int base64_value(char c) {
  if (c >= 'A' && c <= 'Z') return c - 'A';
  if (c >= 'a' && c <= 'z') return c - 'a' + 26;
  if (c >= '0' && c <= '9') return c - '0' + 52;
  if (c == '+') return 62;
  if (c == '/') return 63;
  return -1;
}

bool supported_hash(std::string_view hash) {
  for (const std::string_view prefix : {"$6$", "$5$", "$2b$", "$2y$", "$y$"})
    if (hash.starts_with(prefix)) return true;
  return false;
}

// The hashes are compared in a time that does not depend on where they differ.
bool same_bytes(const char* a, const char* b, std::size_t size) {
  unsigned char difference = 0;
  for (std::size_t i = 0; i < size; ++i) difference |= static_cast<unsigned char>(a[i] ^ b[i]);
  return difference == 0;
}

}  // namespace

std::optional<std::string> decode_base64(std::string_view text) {
  while (!text.empty() && text.back() == '=') text.remove_suffix(1);
  if (text.size() % 4 == 1) return std::nullopt;
  std::string out;
  std::uint32_t bits = 0;
  int count = 0;
  for (const char c : text) {
    const int value = base64_value(c);
    if (value < 0) return std::nullopt;
    bits = bits << 6 | static_cast<std::uint32_t>(value);
    if (++count == 4) {
      out.push_back(static_cast<char>(bits >> 16));
      out.push_back(static_cast<char>(bits >> 8));
      out.push_back(static_cast<char>(bits));
      bits = 0;
      count = 0;
    }
  }
  if (count == 2) out.push_back(static_cast<char>(bits >> 4));
  if (count == 3) {
    out.push_back(static_cast<char>(bits >> 10));
    out.push_back(static_cast<char>(bits >> 2));
  }
  return out;
}

// crypt_rn computes into a buffer of its own: no static state, nothing kept.
bool hash_matches(const std::string& password, const std::string& hash) {
  auto data = std::make_unique<crypt_data>();
  const char* computed = crypt_rn(password.c_str(), hash.c_str(), data.get(), sizeof(crypt_data));
  const bool same = computed != nullptr && computed[0] != '*' && std::strlen(computed) == hash.size() &&
                    same_bytes(computed, hash.data(), hash.size());
  explicit_bzero(data.get(), sizeof(crypt_data));
  return same;
}

void forget_password(std::string& password) {
  explicit_bzero(password.data(), password.size());
  password.clear();
}

BasicAuth BasicAuth::load(const std::string& path, const std::string& key_origin) {
  const auto origin = (key_origin.empty() ? std::string() : key_origin + ": ") + "http.users " + path;
  std::ifstream file(path);
  if (!file) throw std::runtime_error(fmt::format("{}: {}", origin, std::strerror(errno)));
  std::ostringstream text;
  text << file.rdbuf();
  return parse(text.str(), origin);
}

BasicAuth BasicAuth::parse(std::string_view text, const std::string& origin) {
  BasicAuth auth;
  std::size_t number = 0;
  while (!text.empty()) {
    const auto end = text.find('\n');
    auto line = text.substr(0, end);
    text.remove_prefix(end == std::string_view::npos ? text.size() : end + 1);
    ++number;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    if (line.empty() || line.front() == '#') continue;
    const auto colon = line.find(':');
    if (colon == 0 || colon == std::string_view::npos)
      throw std::runtime_error(fmt::format("{}:{}: expected name:password-hash", origin, number));
    const std::string name(line.substr(0, colon));
    const std::string hash(line.substr(colon + 1));
    if (!supported_hash(hash))
      throw std::runtime_error(fmt::format("{}:{}: '{}' has no password hash crypt(3) reads ($6$, $5$, $2b$, $2y$ or $y$; "
                                           "make one with `openssl passwd -6`)", origin, number, name));
    if (!auth.hashes_.emplace(name, hash).second)
      throw std::runtime_error(fmt::format("{}:{}: '{}' is listed twice", origin, number, name));
  }
  if (auth.hashes_.empty()) throw std::runtime_error(fmt::format("{}: lists no user", origin));
  return auth;
}

void BasicAuth::remember(const PasswordCheck& passed) {
  if (passed_.contains(passed.authorization)) return;
  if (passed_.size() >= remembered) {
    passed_.erase(passed_order_.front());
    passed_order_.pop_front();
  }
  passed_.emplace(passed.authorization, passed.user);
  passed_order_.push_back(passed.authorization);
}

BasicAuth::Judgement BasicAuth::judge(std::string_view authorization) const {
  const std::string header(authorization);
  if (const auto known = passed_.find(header); known != passed_.end()) return {Verdict::allowed, known->second, {}};
  constexpr std::string_view scheme = "Basic ";
  if (authorization.size() <= scheme.size() || !std::equal(scheme.begin(), scheme.end(), authorization.begin(),
                                                           [](char a, char b) {
                                                             return std::tolower(static_cast<unsigned char>(a)) ==
                                                                    std::tolower(static_cast<unsigned char>(b));
                                                           }))
    return {Verdict::refused, {}, {}};
  auto credentials = decode_base64(authorization.substr(scheme.size()));
  const auto colon = credentials ? credentials->find(':') : std::string::npos;
  if (colon == std::string::npos) {
    if (credentials) forget_password(*credentials);
    return {Verdict::refused, {}, {}};
  }
  PasswordCheck check;
  check.authorization = header;
  check.user = credentials->substr(0, colon);
  check.password = credentials->substr(colon + 1);
  forget_password(*credentials);
  const auto hash = hashes_.find(check.user);
  // An unknown name costs a hash too, so that the time of the answer does not tell which names exist.
  check.known_user = hash != hashes_.end();
  check.hash = check.known_user ? hash->second : hashes_.begin()->second;
  return {Verdict::check, {}, std::move(check)};
}

}  // namespace unima::web
