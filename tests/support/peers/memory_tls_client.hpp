#pragma once
// OpenSSL's own TLS client with its bytes in memory instead of on a socket: the peer of the
// bridge's TLS port (SPEC §11). The test carries the bytes, so it decides what travels with
// what — a request in the same piece as the handshake's Finished, a record split anywhere,
// a forged tag — and the client is a TLS implementation other than the port's own records.
// The unit tests hand its bytes to tls::MemorySession directly; SegmentedTlsClient sends
// them to the daemon over a socket.

#include <openssl/ssl.h>

#include <cstdint>
#include <span>
#include <vector>

namespace unima::test_support {

class MemoryTlsClient {
 public:
  /// A client session of `context` (which it keeps a reference of), in the connect state.
  explicit MemoryTlsClient(SSL_CTX* context);
  ~MemoryTlsClient();
  MemoryTlsClient(const MemoryTlsClient&) = delete;
  MemoryTlsClient& operator=(const MemoryTlsClient&) = delete;

  /// The session, for OpenSSL's calls: SSL_do_handshake, SSL_write, SSL_read, SSL_key_update.
  SSL* ssl() const { return ssl_; }
  /// What the client wrote for its peer since the last call.
  std::vector<std::uint8_t> take_output();
  /// Bytes from its peer, read by the client's next call.
  void give_input(std::span<const std::uint8_t> bytes);

 private:
  SSL* ssl_ = nullptr;
  BIO* in_ = nullptr;
  BIO* out_ = nullptr;
};

}  // namespace unima::test_support
