#pragma once
// The server's side of a TLS 1.3 connection once its handshake is done (RFC 8446 §5, §4.6.3,
// §6): records cut from the stream of ciphertext and opened, application data out of them,
// answers sealed into records, the client's KeyUpdate followed (and answered when it asks),
// close_notify and other alerts, and a KeyUpdate of its own before the AEAD's limit.
// A requested KeyUpdate is answered once before the next answer, however many requests
// came while the server was silent (§4.6.3).
// Everything a TLS 1.3 client may send after its Finished is handled here; anything else
// ends the connection. Bytes in, bytes out: no socket, no SSL*.

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "tls/traffic_protection.hpp"

namespace unima::tls {

class RecordLayer {
 public:
  /// Records sealed under one key before the server moves to the next (RFC 8446 §5.5 puts
  /// AES-GCM's limit at 2^24.5 records).
  static constexpr std::uint64_t default_records_per_key = std::uint64_t{1} << 24;
  /// Records in a row that carry no application data (KeyUpdates, user_canceled, empty
  /// records) before the connection counts as a flood: each KeyUpdate costs a key
  /// derivation, far more than the 22 bytes that ask for it.
  static constexpr int max_records_without_data = 16;

  /// The client's and the server's application traffic secrets (the first generation).
  RecordLayer(std::uint16_t cipher_suite, std::span<const std::uint8_t> client_secret,
              std::span<const std::uint8_t> server_secret, std::uint64_t records_per_key = default_records_per_key);

  enum class Status : std::uint8_t {
    done,        // `n` bytes of plaintext
    want_input,  // nothing more until more ciphertext is fed
    closed,      // the client's close_notify
    failed,      // error() says why; the connection is over
  };

  /// Ciphertext from the client.
  void feed(std::span<const std::uint8_t> ciphertext);
  /// Plaintext of what was fed, up to out.size() bytes, into `n`.
  Status read(std::span<std::uint8_t> out, std::size_t& n);
  /// Seals all of `plaintext` into records in the output.
  void write(std::span<const std::uint8_t> plaintext);
  /// Appends the records waiting to be sent to `out` (and leaves none).
  void take_output(std::vector<std::uint8_t>& out);
  bool has_output() const { return !output_.empty(); }
  const std::string& error() const { return error_; }

 private:
  Status open_next_record();
  Status take_handshake_messages();
  Status fail(std::string why, std::uint8_t alert);
  void seal(ContentType type, std::span<const std::uint8_t> content);

  TrafficProtection receiving_;
  TrafficProtection sending_;
  std::uint64_t records_per_key_;
  std::vector<std::uint8_t> input_;
  std::size_t input_start_ = 0;
  std::vector<std::uint8_t> plaintext_;
  std::size_t plaintext_start_ = 0;
  std::vector<std::uint8_t> handshake_;  // post-handshake messages, possibly split across records
  std::vector<std::uint8_t> output_;
  bool key_update_owed_ = false;  // the client asked for one (RFC 8446 §4.6.3)
  int records_without_data_ = 0;
  Status ended_ = Status::done;  // closed or failed once the connection is over
  std::string error_;
};

}  // namespace unima::tls
