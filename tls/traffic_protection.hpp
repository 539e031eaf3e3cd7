#pragma once
// TLS 1.3's protection of the records of one direction (RFC 8446 §5.2, §5.3, §7.1–7.3):
// the key and IV of a traffic secret, each record's nonce from its sequence number, the
// inner content type behind the plaintext, and the next secret after a KeyUpdate. The
// AEAD is OpenSSL's; the port's handshake stays OpenSSL's (tls/memory_session hands the
// records over once it is done, as OpenSSL hands them to the kernel's TLS). No I/O.

#include <openssl/evp.h>

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace unima::tls {

enum class ContentType : std::uint8_t { alert = 21, handshake = 22, application_data = 23 };

inline constexpr std::size_t record_header_size = 5;
inline constexpr std::size_t aead_tag_size = 16;
inline constexpr std::size_t max_record_plaintext = 1 << 14;
// RFC 8446 §5.2: the ciphertext of a record is at most 2^14 + 256 bytes.
inline constexpr std::size_t max_record_ciphertext = max_record_plaintext + 256;

class TrafficProtection {
 public:
  /// True for the cipher suites this protects (TLS_AES_128_GCM_SHA256,
  /// TLS_AES_256_GCM_SHA384, TLS_CHACHA20_POLY1305_SHA256), by their IANA number.
  static bool protects(std::uint16_t cipher_suite);

  /// The protection of `secret` (the direction's traffic secret) under `cipher_suite`;
  /// `sealing` for the records this side sends. Throws std::runtime_error if OpenSSL fails.
  TrafficProtection(std::uint16_t cipher_suite, std::span<const std::uint8_t> secret, bool sealing);
  ~TrafficProtection();
  TrafficProtection(const TrafficProtection&) = delete;
  TrafficProtection& operator=(const TrafficProtection&) = delete;

  /// Appends one record of `type` holding `content` (at most max_record_plaintext bytes).
  void seal(ContentType type, std::span<const std::uint8_t> content, std::vector<std::uint8_t>& out);

  struct Opened {
    ContentType type;
    std::span<std::uint8_t> content;  // inside the record that was opened
  };
  /// Opens `record` (header and ciphertext, whole) in place; nothing if it is not authentic
  /// or its inner plaintext has no content type.
  std::optional<Opened> open(std::span<std::uint8_t> record);

  /// After a KeyUpdate: the next traffic secret, its key and IV, sequence numbers from 0.
  void next_generation();
  /// Records sealed or opened under the current key.
  std::uint64_t records() const { return sequence_; }

 private:
  void key_from_secret();
  const std::uint8_t* nonce();

  const EVP_CIPHER* cipher_;
  const EVP_MD* digest_;
  std::vector<std::uint8_t> secret_;
  std::array<std::uint8_t, 12> iv_{};
  std::array<std::uint8_t, 12> nonce_{};
  EVP_CIPHER_CTX* context_;
  bool sealing_;
  std::uint64_t sequence_ = 0;
};

}  // namespace unima::tls
