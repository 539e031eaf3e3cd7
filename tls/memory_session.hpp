#pragma once
// A server's TLS session whose records go through memory, not a socket: the port reads
// ciphertext from its socket as it reads plain Modbus/TCP and feeds it in, takes the
// ciphertext out and sends it with the same non-blocking send as a plain answer
// (io/modbus/tcp_slave_server). So a TLS request costs the same system calls as a plain one and
// no layer of asynchronous operations of its own. Everything of TLS is OpenSSL's — the
// handshake, every record of TLS 1.2 and 1.3, alerts, close_notify (SPEC §11): this only
// carries bytes between OpenSSL's memory BIOs and the port. No sockets, no Asio: testable on bytes.

#include <openssl/ssl.h>

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace unima::tls {

class MemorySession {
 public:
  /// A server session of `context` (load_server_credentials's).
  explicit MemorySession(SSL_CTX* context);
  ~MemorySession();
  MemorySession(const MemorySession&) = delete;
  MemorySession& operator=(const MemorySession&) = delete;

  // done — handshake: complete; read: `n` bytes of plaintext. want_input — nothing more
  // until more ciphertext is fed. closed — the peer's close_notify. failed — error() says why.
  enum class Status { done, want_input, closed, failed };

  /// Ciphertext from the peer.
  void feed(std::span<const std::uint8_t> ciphertext);
  /// Moves the handshake on with what was fed; its answers wait in the output.
  Status handshake();
  bool handshaken() const { return handshaken_; }
  /// Plaintext of what was fed, up to out.size() bytes, into `n`.
  Status read(std::span<std::uint8_t> out, std::size_t& n);
  /// Encrypts all of `plaintext` into the output; false (error() says why) on a failure.
  bool write(std::span<const std::uint8_t> plaintext);
  /// Puts this side's close_notify in the output, once, for a clean close of a session whose
  /// handshake completed and that did not fail (OpenSSL sends nothing more after a fatal
  /// error). False when there is nothing to say goodbye to.
  bool close_notify();
  /// Appends the ciphertext waiting to be sent to `out` (and leaves none).
  void take_output(std::vector<std::uint8_t>& out);
  bool has_output() const;

  SSL* native_handle() const { return ssl_; }
  const std::string& error() const { return error_; }

 private:
  Status status_of(int result);

  SSL* ssl_ = nullptr;
  BIO* in_ = nullptr;   // owned by ssl_
  BIO* out_ = nullptr;  // owned by ssl_
  bool handshaken_ = false;
  bool failed_ = false;
  bool said_goodbye_ = false;
  std::string error_;
};

}  // namespace unima::tls
