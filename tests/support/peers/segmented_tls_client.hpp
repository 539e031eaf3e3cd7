#pragma once
// A Modbus/TCP Security client of the running daemon (SPEC §11) whose TLS bytes the test
// sends itself: the MemoryTlsClient over a loopback socket, so that the test decides what
// goes out in which segment (a request with the handshake's Finished), when the client
// renews its keys, and whether a record's tag is forged.

#include <openssl/ssl.h>

#include <chrono>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "tests/support/loopback.hpp"
#include "tests/support/peers/memory_tls_client.hpp"

namespace unima::test_support {

class SegmentedTlsClient {
 public:
  /// Connects to 127.0.0.1:port, to present `certificate` with its `key` (PEM files).
  SegmentedTlsClient(std::uint16_t port, const std::string& certificate, const std::string& key);
  ~SegmentedTlsClient();
  SegmentedTlsClient(const SegmentedTlsClient&) = delete;
  SegmentedTlsClient& operator=(const SegmentedTlsClient&) = delete;

  /// The handshake up to the client's Finished, which waits in the output. False if it fails.
  bool handshake();
  /// Puts `request` in the output: it goes with whatever is there in the next flush.
  void write(std::span<const std::uint8_t> request);
  /// Sends the output in one segment; `forged`: with the last bit of its last record's tag flipped.
  void flush(bool forged = false);
  /// OpenSSL's reason for the last failure, e.g. the alert the server sent.
  static std::string last_error();
  /// The plaintext of the answer, waiting up to 2 s for each piece; empty if none came.
  std::vector<std::uint8_t> answer();
  /// Sends the client's close_notify.
  void close_notify();
  /// True when the server's close_notify comes within `timeout` (SSL_read gives 0 with
  /// SSL_ERROR_ZERO_RETURN); false when the connection ends without one, or nothing comes.
  bool closed_with_close_notify(std::chrono::milliseconds timeout);
  SSL* ssl() const { return client_.ssl(); }

 private:
  bool receive();

  bool loaded_ = false;  // before context_, which sets it
  SSL_CTX* context_;
  MemoryTlsClient client_;
  Socket socket_;
};

}  // namespace unima::test_support
