#include "tls/traffic_protection.hpp"

#include <openssl/core_names.h>
#include <openssl/crypto.h>
#include <openssl/kdf.h>

#include <cstring>
#include <stdexcept>
#include <string>
#include <string_view>

namespace unima::tls {

namespace {

struct Suite {
  const EVP_CIPHER* cipher;
  const EVP_MD* digest;
};

// Fetched once: a fetch takes OpenSSL's provider locks, and every connection needs them.
const EVP_CIPHER* fetched_cipher(const char* name) {
  const EVP_CIPHER* cipher = EVP_CIPHER_fetch(nullptr, name, nullptr);
  if (cipher == nullptr) throw std::runtime_error(std::string("OpenSSL has no ") + name);
  return cipher;
}

const EVP_MD* fetched_digest(const char* name) {
  const EVP_MD* digest = EVP_MD_fetch(nullptr, name, nullptr);
  if (digest == nullptr) throw std::runtime_error(std::string("OpenSSL has no ") + name);
  return digest;
}

Suite suite_of(std::uint16_t cipher_suite) {
  switch (cipher_suite) {
    case 0x1301: {
      static const Suite suite{fetched_cipher("AES-128-GCM"), fetched_digest("SHA256")};
      return suite;
    }
    case 0x1302: {
      static const Suite suite{fetched_cipher("AES-256-GCM"), fetched_digest("SHA384")};
      return suite;
    }
    case 0x1303: {
      static const Suite suite{fetched_cipher("ChaCha20-Poly1305"), fetched_digest("SHA256")};
      return suite;
    }
    default:
      throw std::runtime_error("not a TLS 1.3 cipher suite this port protects");
  }
}

// HKDF-Expand-Label(secret, label, "", length), RFC 8446 §7.1.
std::vector<std::uint8_t> expand_label(const EVP_MD* digest, std::span<const std::uint8_t> secret,
                                       std::string_view label, std::size_t length) {
  const std::string full_label = "tls13 " + std::string(label);
  std::vector<std::uint8_t> info{static_cast<std::uint8_t>(length >> 8), static_cast<std::uint8_t>(length),
                                 static_cast<std::uint8_t>(full_label.size())};
  info.insert(info.end(), full_label.begin(), full_label.end());
  info.push_back(0);  // an empty context

  static EVP_KDF* const hkdf = EVP_KDF_fetch(nullptr, OSSL_KDF_NAME_HKDF, nullptr);  // once, as the ciphers
  EVP_KDF_CTX* context = hkdf ? EVP_KDF_CTX_new(hkdf) : nullptr;
  int mode = EVP_KDF_HKDF_MODE_EXPAND_ONLY;
  const OSSL_PARAM parameters[] = {
      OSSL_PARAM_construct_int(OSSL_KDF_PARAM_MODE, &mode),
      OSSL_PARAM_construct_utf8_string(OSSL_KDF_PARAM_DIGEST, const_cast<char*>(EVP_MD_get0_name(digest)), 0),
      OSSL_PARAM_construct_octet_string(OSSL_KDF_PARAM_KEY, const_cast<std::uint8_t*>(secret.data()), secret.size()),
      OSSL_PARAM_construct_octet_string(OSSL_KDF_PARAM_INFO, info.data(), info.size()),
      OSSL_PARAM_construct_end()};
  std::vector<std::uint8_t> out(length);
  const bool derived = context != nullptr && EVP_KDF_derive(context, out.data(), out.size(), parameters) == 1;
  EVP_KDF_CTX_free(context);
  if (!derived) throw std::runtime_error("OpenSSL cannot derive a TLS 1.3 traffic key");
  return out;
}

}  // namespace

bool TrafficProtection::protects(std::uint16_t cipher_suite) { return cipher_suite >= 0x1301 && cipher_suite <= 0x1303; }

TrafficProtection::TrafficProtection(std::uint16_t cipher_suite, std::span<const std::uint8_t> secret, bool sealing)
    : cipher_(suite_of(cipher_suite).cipher),
      digest_(suite_of(cipher_suite).digest),
      secret_(secret.begin(), secret.end()),
      context_(EVP_CIPHER_CTX_new()),
      sealing_(sealing) {
  if (context_ == nullptr) throw std::runtime_error("OpenSSL cannot make a cipher context");
  if (secret_.size() != static_cast<std::size_t>(EVP_MD_get_size(digest_))) {
    EVP_CIPHER_CTX_free(context_);
    throw std::runtime_error("a TLS 1.3 traffic secret of the wrong size");
  }
  key_from_secret();
}

TrafficProtection::~TrafficProtection() {
  OPENSSL_cleanse(secret_.data(), secret_.size());
  OPENSSL_cleanse(iv_.data(), iv_.size());
  EVP_CIPHER_CTX_free(context_);
}

// RFC 8446 §7.3: the key and IV of a traffic secret; the key lives on in the cipher context.
void TrafficProtection::key_from_secret() {
  auto key = expand_label(digest_, secret_, "key", static_cast<std::size_t>(EVP_CIPHER_get_key_length(cipher_)));
  const auto iv = expand_label(digest_, secret_, "iv", iv_.size());
  std::memcpy(iv_.data(), iv.data(), iv_.size());
  const bool keyed = EVP_CipherInit_ex(context_, cipher_, nullptr, key.data(), nullptr, sealing_ ? 1 : 0) == 1;
  OPENSSL_cleanse(key.data(), key.size());
  if (!keyed) throw std::runtime_error("OpenSSL cannot key the record cipher");
  sequence_ = 0;
}

void TrafficProtection::next_generation() {
  auto next = expand_label(digest_, secret_, "traffic upd", secret_.size());
  OPENSSL_cleanse(secret_.data(), secret_.size());
  secret_.swap(next);
  key_from_secret();
}

// RFC 8446 §5.3: the IV with the 64-bit sequence number XORed into its last 8 bytes.
const std::uint8_t* TrafficProtection::nonce() {
  nonce_ = iv_;
  for (std::size_t i = 0; i < 8; ++i) nonce_[nonce_.size() - 1 - i] ^= static_cast<std::uint8_t>(sequence_ >> (8 * i));
  return nonce_.data();
}

void TrafficProtection::seal(ContentType type, std::span<const std::uint8_t> content, std::vector<std::uint8_t>& out) {
  if (content.size() > max_record_plaintext) throw std::logic_error("a TLS record's plaintext is at most 16 KiB");
  const std::size_t inner_size = content.size() + 1;
  const std::size_t length = inner_size + aead_tag_size;
  const std::size_t at = out.size();
  out.resize(at + record_header_size + length);
  std::uint8_t* record = out.data() + at;
  // TLS 1.3's outer header: application_data, the legacy version 3.3, the length.
  record[0] = static_cast<std::uint8_t>(ContentType::application_data);
  record[1] = 3;
  record[2] = 3;
  record[3] = static_cast<std::uint8_t>(length >> 8);
  record[4] = static_cast<std::uint8_t>(length);
  std::uint8_t* body = record + record_header_size;
  if (!content.empty()) std::memcpy(body, content.data(), content.size());
  body[content.size()] = static_cast<std::uint8_t>(type);
  int n = 0;
  const bool sealed = EVP_CipherInit_ex(context_, nullptr, nullptr, nullptr, nonce(), -1) == 1 &&
                      EVP_CipherUpdate(context_, nullptr, &n, record, record_header_size) == 1 &&
                      EVP_CipherUpdate(context_, body, &n, body, static_cast<int>(inner_size)) == 1 &&
                      EVP_CipherFinal_ex(context_, body + inner_size, &n) == 1 &&
                      EVP_CIPHER_CTX_ctrl(context_, EVP_CTRL_AEAD_GET_TAG, aead_tag_size, body + inner_size) == 1;
  if (!sealed) {
    out.resize(at);
    throw std::runtime_error("OpenSSL cannot seal a record");
  }
  ++sequence_;
}

std::optional<TrafficProtection::Opened> TrafficProtection::open(std::span<std::uint8_t> record) {
  if (record.size() < record_header_size + 1 + aead_tag_size) return std::nullopt;
  auto body = record.subspan(record_header_size);
  const std::size_t inner_size = body.size() - aead_tag_size;
  int n = 0;
  const bool authentic = EVP_CipherInit_ex(context_, nullptr, nullptr, nullptr, nonce(), -1) == 1 &&
                         EVP_CipherUpdate(context_, nullptr, &n, record.data(), record_header_size) == 1 &&
                         EVP_CipherUpdate(context_, body.data(), &n, body.data(), static_cast<int>(inner_size)) == 1 &&
                         EVP_CIPHER_CTX_ctrl(context_, EVP_CTRL_AEAD_SET_TAG, aead_tag_size, body.data() + inner_size) == 1 &&
                         EVP_CipherFinal_ex(context_, body.data() + inner_size, &n) == 1;
  if (!authentic) return std::nullopt;
  ++sequence_;
  // RFC 8446 §5.4: zeros pad the inner plaintext; the last byte that is not zero is its type.
  std::size_t end = inner_size;
  while (end > 0 && body[end - 1] == 0) --end;
  if (end == 0) return std::nullopt;
  return Opened{static_cast<ContentType>(body[end - 1]), body.first(end - 1)};
}

}  // namespace unima::tls
