#include "tests/support/peers/segmented_tls_client.hpp"

#include <gtest/gtest.h>
#include <openssl/err.h>

#include <algorithm>
#include <chrono>

namespace unima::test_support {

namespace {
SSL_CTX* client_context(const std::string& certificate, const std::string& key, bool& loaded) {
  SSL_CTX* context = SSL_CTX_new(TLS_client_method());
  loaded = SSL_CTX_use_certificate_file(context, certificate.c_str(), SSL_FILETYPE_PEM) == 1 &&
           SSL_CTX_use_PrivateKey_file(context, key.c_str(), SSL_FILETYPE_PEM) == 1;
  return context;
}
}  // namespace

SegmentedTlsClient::SegmentedTlsClient(std::uint16_t port, const std::string& certificate, const std::string& key)
    : context_(client_context(certificate, key, loaded_)), client_(context_), socket_(Socket::tcp(port)) {}

SegmentedTlsClient::~SegmentedTlsClient() { SSL_CTX_free(context_); }

bool SegmentedTlsClient::handshake() {
  if (!loaded_) return false;
  while (SSL_do_handshake(client_.ssl()) != 1) {
    flush();
    if (!receive()) return false;
  }
  return true;
}

void SegmentedTlsClient::write(std::span<const std::uint8_t> request) {
  EXPECT_EQ(SSL_write(client_.ssl(), request.data(), static_cast<int>(request.size())), static_cast<int>(request.size()));
}

void SegmentedTlsClient::flush(bool forged) {
  auto bytes = client_.take_output();
  if (forged && !bytes.empty()) bytes.back() ^= 1;
  if (!bytes.empty()) socket_.send(bytes);
}

std::string SegmentedTlsClient::last_error() {
  const unsigned long code = ERR_get_error();
  return code != 0 && ERR_reason_error_string(code) ? ERR_reason_error_string(code) : "none";
}

std::vector<std::uint8_t> SegmentedTlsClient::answer() {
  std::vector<std::uint8_t> answer(260);
  int got = -1;
  for (int tries = 0; tries < 5 && got <= 0; ++tries) {
    got = SSL_read(client_.ssl(), answer.data(), static_cast<int>(answer.size()));
    if (got <= 0 && !receive()) break;
  }
  answer.resize(static_cast<std::size_t>(std::max(got, 0)));
  return answer;
}

void SegmentedTlsClient::close_notify() {
  SSL_shutdown(client_.ssl());
  flush();
}

bool SegmentedTlsClient::closed_with_close_notify(std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  std::uint8_t plaintext[260];
  while (true) {
    const int got = SSL_read(client_.ssl(), plaintext, sizeof plaintext);
    if (got > 0) continue;  // an answer still on its way
    const int error = SSL_get_error(client_.ssl(), got);
    if (error == SSL_ERROR_ZERO_RETURN) return true;
    if (error != SSL_ERROR_WANT_READ) return false;
    std::uint8_t buffer[16384];
    const auto n = read_before(socket_.fd(), deadline, buffer);
    if (n <= 0) return false;  // the end of the stream without a close_notify, or the deadline
    client_.give_input(std::span(buffer, static_cast<std::size_t>(n)));
  }
}

bool SegmentedTlsClient::receive() {
  std::uint8_t buffer[16384];
  const auto n = read_before(socket_.fd(), std::chrono::steady_clock::now() + std::chrono::seconds(2), buffer);
  if (n > 0) client_.give_input(std::span(buffer, static_cast<std::size_t>(n)));
  return n > 0;
}

}  // namespace unima::test_support
