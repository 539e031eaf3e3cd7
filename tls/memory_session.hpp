#pragma once
// A server's TLS session whose records go through memory, not a socket: the port reads
// ciphertext from its socket as it reads plain Modbus/TCP and feeds it in, takes the
// ciphertext out and sends it with the same non-blocking send as a plain answer
// (io/modbus/tcp_slave_server). So a TLS request costs the same system calls as a plain one and
// no layer of asynchronous operations of its own. OpenSSL does the handshake; after a TLS
// 1.3 handshake the records are tls/record_layer's, on OpenSSL's AEAD, which costs the
// port less than half of OpenSSL 3.0's record layer per request (docs/performance.md,
// docs/security.md); after TLS 1.2 they stay OpenSSL's. No sockets, no Asio: testable on bytes.

#include <openssl/ssl.h>

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "tls/record_layer.hpp"

namespace unima::tls {

class MemorySession {
 public:
  /// A server session of `context` (load_server_credentials's). Sets the context's key-log
  /// callback, OpenSSL 3.0's only way to a connection's traffic secrets, unless one is set.
  explicit MemorySession(SSL_CTX* context);
  ~MemorySession();
  MemorySession(const MemorySession&) = delete;
  MemorySession& operator=(const MemorySession&) = delete;

  // done — handshake: complete; read: `n` bytes of plaintext. want_input — nothing more
  // until more ciphertext is fed. closed — the peer's close_notify. failed — error() says why.
  using Status = RecordLayer::Status;

  /// Ciphertext from the peer.
  void feed(std::span<const std::uint8_t> ciphertext);
  /// Moves the handshake on with what was fed; its answers wait in the output.
  Status handshake();
  bool handshaken() const { return handshaken_; }
  /// Plaintext of what was fed, up to out.size() bytes, into `n`.
  Status read(std::span<std::uint8_t> out, std::size_t& n);
  /// Encrypts all of `plaintext` into the output; false (error() says why) on a failure.
  bool write(std::span<const std::uint8_t> plaintext);
  /// Appends the ciphertext waiting to be sent to `out` (and leaves none).
  void take_output(std::vector<std::uint8_t>& out);
  bool has_output() const;

  /// True once tls/record_layer protects the records instead of OpenSSL.
  bool records_own() const { return records_.has_value(); }
  SSL* native_handle() const { return ssl_; }
  const std::string& error() const { return error_; }

  /// What the key-log callback keeps of a handshake: the first application traffic secrets.
  struct TrafficSecrets {
    std::vector<std::uint8_t> client;
    std::vector<std::uint8_t> server;
    void forget();
    ~TrafficSecrets() { forget(); }
  };

 private:
  Status status_of(int result);
  void take_over_records();

  SSL* ssl_ = nullptr;
  BIO* in_ = nullptr;   // owned by ssl_
  BIO* out_ = nullptr;  // owned by ssl_
  bool handshaken_ = false;
  TrafficSecrets secrets_;
  std::optional<RecordLayer> records_;
  std::vector<std::uint8_t> handshake_tail_;  // OpenSSL's last output when the records became ours
  std::string error_;
};

}  // namespace unima::tls
