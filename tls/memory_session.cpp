#include "tls/memory_session.hpp"

#include <openssl/err.h>

#include <stdexcept>

namespace unima::tls {

MemorySession::MemorySession(SSL_CTX* context) : ssl_(SSL_new(context)) {
  if (ssl_ == nullptr) throw std::runtime_error("OpenSSL cannot make a session");
  in_ = BIO_new(BIO_s_mem());
  out_ = BIO_new(BIO_s_mem());
  // An empty input is "more to come", not the end of the stream.
  BIO_set_mem_eof_return(in_, -1);
  BIO_set_mem_eof_return(out_, -1);
  SSL_set_bio(ssl_, in_, out_);
  // OpenSSL takes all that was fed in one BIO read instead of a record's header and then
  // its body; whatever it read ahead stays in the session (SSL_has_pending, read()).
  SSL_set_read_ahead(ssl_, 1);
  SSL_set_accept_state(ssl_);
}

MemorySession::~MemorySession() { SSL_free(ssl_); }

void MemorySession::feed(std::span<const std::uint8_t> ciphertext) {
  if (!ciphertext.empty()) BIO_write(in_, ciphertext.data(), static_cast<int>(ciphertext.size()));
}

MemorySession::Status MemorySession::status_of(int result) {
  switch (SSL_get_error(ssl_, result)) {
    case SSL_ERROR_WANT_READ:
    case SSL_ERROR_WANT_WRITE:  // a memory BIO takes everything: only while a handshake waits
      return Status::want_input;
    case SSL_ERROR_ZERO_RETURN:
      return Status::closed;
    default: {
      failed_ = true;
      const unsigned long code = ERR_get_error();
      error_ = code != 0 && ERR_reason_error_string(code) ? ERR_reason_error_string(code) : "TLS protocol error";
      ERR_clear_error();
      return Status::failed;
    }
  }
}

MemorySession::Status MemorySession::handshake() {
  if (handshaken()) return Status::done;
  const int result = SSL_do_handshake(ssl_);
  if (result != 1) return status_of(result);
  handshaken_ = true;
  return Status::done;
}

MemorySession::Status MemorySession::read(std::span<std::uint8_t> out, std::size_t& n) {
  n = 0;
  if (out.empty()) return Status::done;
  // Nothing fed and nothing buffered (SSL_has_pending counts records read ahead):
  // SSL_read could only fail with WANT_READ by way of OpenSSL's error queue, and the port
  // asks once more after each request's record.
  if (BIO_ctrl_pending(in_) == 0 && SSL_has_pending(ssl_) == 0) return Status::want_input;
  const int result = SSL_read(ssl_, out.data(), static_cast<int>(out.size()));
  if (result > 0) {
    n = static_cast<std::size_t>(result);
    return Status::done;
  }
  return status_of(result);
}

bool MemorySession::write(std::span<const std::uint8_t> plaintext) {
  if (plaintext.empty()) return true;
  const int result = SSL_write(ssl_, plaintext.data(), static_cast<int>(plaintext.size()));
  if (result == static_cast<int>(plaintext.size())) return true;
  status_of(result);
  return false;
}

// OpenSSL must not be asked for a shutdown after a fatal error (SSL_shutdown(3)); its
// first call writes the alert, and the port does not wait for the peer's answer to it.
bool MemorySession::close_notify() {
  if (!handshaken_ || failed_ || said_goodbye_) return false;
  said_goodbye_ = true;
  const int result = SSL_shutdown(ssl_);
  ERR_clear_error();  // a peer gone already is no news for the next session on this thread
  return result >= 0 && has_output();
}

void MemorySession::take_output(std::vector<std::uint8_t>& out) {
  const auto pending = BIO_ctrl_pending(out_);
  if (pending == 0) return;
  const auto at = out.size();
  out.resize(at + pending);
  const int taken = BIO_read(out_, out.data() + at, static_cast<int>(pending));
  out.resize(at + static_cast<std::size_t>(taken > 0 ? taken : 0));
}

bool MemorySession::has_output() const { return BIO_ctrl_pending(out_) > 0; }

}  // namespace unima::tls
