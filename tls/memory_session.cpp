#include "tls/memory_session.hpp"

#include "tls/key_log.hpp"

#include <openssl/crypto.h>
#include <openssl/err.h>

#include <stdexcept>

namespace unima::tls {

namespace {

int secrets_index() {
  static const int index = SSL_get_ex_new_index(0, nullptr, nullptr, nullptr, nullptr);
  return index;
}

// OpenSSL calls this with each secret of a handshake (tls/key_log); a session keeps the two
// it needs, in memory only.
void keep_application_secrets(const SSL* ssl, const char* line) {
  auto* secrets = static_cast<MemorySession::TrafficSecrets*>(SSL_get_ex_data(ssl, secrets_index()));
  if (secrets == nullptr) return;
  // A secret with broken hex stays empty, and OpenSSL keeps the records (take_over_records).
  if (!read_key_log_secret(line, "CLIENT_TRAFFIC_SECRET_0", secrets->client))
    read_key_log_secret(line, "SERVER_TRAFFIC_SECRET_0", secrets->server);
}

// Appends what `bio` holds to `out`.
void take_pending(BIO* bio, std::vector<std::uint8_t>& out) {
  const auto pending = BIO_ctrl_pending(bio);
  if (pending == 0) return;
  const auto at = out.size();
  out.resize(at + pending);
  const int taken = BIO_read(bio, out.data() + at, static_cast<int>(pending));
  out.resize(at + static_cast<std::size_t>(taken > 0 ? taken : 0));
}

}  // namespace

void MemorySession::TrafficSecrets::forget() {
  OPENSSL_cleanse(client.data(), client.size());
  OPENSSL_cleanse(server.data(), server.size());
  client.clear();
  server.clear();
}

MemorySession::MemorySession(SSL_CTX* context) : ssl_(SSL_new(context)) {
  if (ssl_ == nullptr) throw std::runtime_error("OpenSSL cannot make a session");
  if (SSL_CTX_get_keylog_callback(context) == nullptr) SSL_CTX_set_keylog_callback(context, keep_application_secrets);
  SSL_set_ex_data(ssl_, secrets_index(), &secrets_);
  in_ = BIO_new(BIO_s_mem());
  out_ = BIO_new(BIO_s_mem());
  // An empty input is "more to come", not the end of the stream.
  BIO_set_mem_eof_return(in_, -1);
  BIO_set_mem_eof_return(out_, -1);
  SSL_set_bio(ssl_, in_, out_);
  // No read-ahead in the handshake: what comes after the client's Finished stays in `in_`
  // for the records' new owner (take_over_records).
  SSL_set_read_ahead(ssl_, 0);
  SSL_set_accept_state(ssl_);
}

MemorySession::~MemorySession() { SSL_free(ssl_); }

void MemorySession::feed(std::span<const std::uint8_t> ciphertext) {
  if (records_) return records_->feed(ciphertext);
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
  take_over_records();
  return Status::done;
}

// The records after a TLS 1.3 handshake are record_layer's when OpenSSL has nothing of
// them: no session tickets it would have sent under the server's key, nothing it read
// ahead. The sequence numbers then start at 0 both ways (RFC 8446 §5.3).
void MemorySession::take_over_records() {
  const SSL_CIPHER* cipher = SSL_get_current_cipher(ssl_);
  const auto suite = cipher ? SSL_CIPHER_get_protocol_id(cipher) : 0;
  const bool ours = SSL_version(ssl_) == TLS1_3_VERSION && SSL_get_num_tickets(ssl_) == 0 &&
                    SSL_has_pending(ssl_) == 0 && TrafficProtection::protects(suite) && !secrets_.client.empty() &&
                    !secrets_.server.empty();
  if (ours) {
    try {
      records_.emplace(suite, secrets_.client, secrets_.server);
    } catch (const std::exception&) {
      records_.reset();  // OpenSSL keeps them
    }
  }
  secrets_.forget();
  if (!records_) {
    // Take all that was fed in one BIO read instead of a record's header and then its body.
    SSL_set_read_ahead(ssl_, 1);
    return;
  }
  // From here on the BIOs are not touched: what OpenSSL wrote last waits in
  // handshake_tail_, what came after the client's Finished is the first of its records.
  take_pending(out_, handshake_tail_);
  std::vector<std::uint8_t> rest;
  take_pending(in_, rest);
  records_->feed(rest);
  // OpenSSL's record buffers (about 34 KiB a connection) are not needed any more.
  (void)SSL_free_buffers(ssl_);
}


MemorySession::Status MemorySession::read(std::span<std::uint8_t> out, std::size_t& n) {
  n = 0;
  if (records_) {
    const auto status = records_->read(out, n);
    if (status == Status::failed) error_ = records_->error();
    return status;
  }
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
  if (records_) {
    try {
      records_->write(plaintext);
      return true;
    } catch (const std::exception& e) {
      error_ = e.what();
      return false;
    }
  }
  const int result = SSL_write(ssl_, plaintext.data(), static_cast<int>(plaintext.size()));
  if (result == static_cast<int>(plaintext.size())) return true;
  status_of(result);
  return false;
}

void MemorySession::take_output(std::vector<std::uint8_t>& out) {
  if (!records_) return take_pending(out_, out);
  if (!handshake_tail_.empty()) {
    out.insert(out.end(), handshake_tail_.begin(), handshake_tail_.end());
    handshake_tail_.clear();
  }
  records_->take_output(out);
}

bool MemorySession::has_output() const {
  return records_ ? !handshake_tail_.empty() || records_->has_output() : BIO_ctrl_pending(out_) > 0;
}

}  // namespace unima::tls
