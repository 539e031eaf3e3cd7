#include "tests/support/peers/memory_tls_client.hpp"

namespace unima::test_support {

MemoryTlsClient::MemoryTlsClient(SSL_CTX* context)
    : ssl_(SSL_new(context)), in_(BIO_new(BIO_s_mem())), out_(BIO_new(BIO_s_mem())) {
  // An empty input is "want more" to OpenSSL, not the end of the stream.
  BIO_set_mem_eof_return(in_, -1);
  SSL_set_bio(ssl_, in_, out_);
  SSL_set_connect_state(ssl_);
}

MemoryTlsClient::~MemoryTlsClient() { SSL_free(ssl_); }

std::vector<std::uint8_t> MemoryTlsClient::take_output() {
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(BIO_ctrl_pending(out_)));
  BIO_read(out_, bytes.data(), static_cast<int>(bytes.size()));
  return bytes;
}

void MemoryTlsClient::give_input(std::span<const std::uint8_t> bytes) {
  BIO_write(in_, bytes.data(), static_cast<int>(bytes.size()));
}

}  // namespace unima::test_support
