#include "tls/record_layer.hpp"

#include <algorithm>
#include <array>

#include <fmt/format.h>

namespace unima::tls {

namespace {

// RFC 8446 §4 and §6: the handshake message and the alerts this side meets after the handshake.
constexpr std::uint8_t key_update = 24;
constexpr std::size_t key_update_size = 5;  // type, 24-bit length 1, request_update
constexpr std::uint8_t update_requested = 1;
constexpr std::uint8_t alert_fatal = 2;
constexpr std::uint8_t close_notify = 0;
constexpr std::uint8_t user_canceled = 90;
constexpr std::uint8_t unexpected_message = 10;
constexpr std::uint8_t bad_record_mac = 20;
constexpr std::uint8_t record_overflow = 22;
constexpr std::uint8_t decode_error = 50;

}  // namespace

RecordLayer::RecordLayer(std::uint16_t cipher_suite, std::span<const std::uint8_t> client_secret,
                         std::span<const std::uint8_t> server_secret, std::uint64_t records_per_key)
    : receiving_(cipher_suite, client_secret, false),
      sending_(cipher_suite, server_secret, true),
      records_per_key_(records_per_key) {}

void RecordLayer::feed(std::span<const std::uint8_t> ciphertext) {
  if (ended_ != Status::done || ciphertext.empty()) return;
  if (input_start_ == input_.size()) {
    input_.clear();
    input_start_ = 0;
  } else if (input_start_ > max_record_ciphertext) {
    input_.erase(input_.begin(), input_.begin() + static_cast<std::ptrdiff_t>(input_start_));
    input_start_ = 0;
  }
  input_.insert(input_.end(), ciphertext.begin(), ciphertext.end());
}

RecordLayer::Status RecordLayer::read(std::span<std::uint8_t> out, std::size_t& n) {
  n = 0;
  if (ended_ != Status::done) return ended_;
  if (out.empty()) return Status::done;
  while (plaintext_start_ == plaintext_.size()) {
    plaintext_.clear();
    plaintext_start_ = 0;
    if (const auto status = open_next_record(); status != Status::done) return status;
  }
  n = std::min(out.size(), plaintext_.size() - plaintext_start_);
  std::copy_n(plaintext_.begin() + static_cast<std::ptrdiff_t>(plaintext_start_), n, out.begin());
  plaintext_start_ += n;
  return Status::done;
}

// One whole record off the input: its application data into plaintext_, or what its
// alert or handshake message asks for.
RecordLayer::Status RecordLayer::open_next_record() {
  const std::size_t available = input_.size() - input_start_;
  if (available < record_header_size) return Status::want_input;
  std::uint8_t* record = input_.data() + input_start_;
  const std::size_t length = std::size_t{record[3]} << 8 | record[4];
  if (length > max_record_ciphertext) return fail("a record longer than TLS allows", record_overflow);
  if (available < record_header_size + length) return Status::want_input;
  // RFC 8446 §5: after the handshake every record is protected and says application_data
  // outside (a change_cipher_spec here is unexpected, §5).
  if (record[0] != static_cast<std::uint8_t>(ContentType::application_data))
    return fail(fmt::format("an unprotected record of type {} after the handshake", record[0]), unexpected_message);
  const auto opened = receiving_.open(std::span(record, record_header_size + length));
  input_start_ += record_header_size + length;
  if (!opened) return fail("a record that is not authentic", bad_record_mac);
  if (opened->content.size() > max_record_plaintext) return fail("a record longer than TLS allows", record_overflow);
  // §5.1: the pieces of a handshake message come in consecutive records.
  if (!handshake_.empty() && opened->type != ContentType::handshake)
    return fail("a record between the pieces of a handshake message", unexpected_message);
  const bool data = opened->type == ContentType::application_data && !opened->content.empty();
  records_without_data_ = data ? 0 : records_without_data_ + 1;
  if (records_without_data_ > max_records_without_data)
    return fail(fmt::format("more than {} records in a row without data", max_records_without_data), unexpected_message);
  switch (opened->type) {
    case ContentType::application_data:
      plaintext_.insert(plaintext_.end(), opened->content.begin(), opened->content.end());
      return Status::done;
    case ContentType::handshake:
      if (opened->content.empty()) return fail("an empty handshake record", unexpected_message);  // §5.1
      handshake_.insert(handshake_.end(), opened->content.begin(), opened->content.end());
      return take_handshake_messages();
    case ContentType::alert: {
      if (opened->content.size() != 2) return fail("a malformed alert", decode_error);
      const auto description = opened->content[1];
      if (description == user_canceled) return Status::done;  // a close_notify follows (§6.1)
      if (description == close_notify) {
        ended_ = Status::closed;
        return ended_;
      }
      ended_ = Status::failed;
      error_ = fmt::format("the client sent alert {}", description);
      return ended_;
    }
  }
  return fail(fmt::format("a record of inner type {}", static_cast<unsigned>(opened->type)), unexpected_message);
}

// RFC 8446 §4.6.3: the only handshake message a client sends a server that asked for no
// certificate after the handshake is KeyUpdate. It must end its record.
RecordLayer::Status RecordLayer::take_handshake_messages() {
  if (handshake_.empty()) return Status::done;
  if (handshake_[0] != key_update)
    return fail(fmt::format("a handshake message of type {} after the handshake", handshake_[0]), unexpected_message);
  if (handshake_.size() < key_update_size) return Status::done;  // the rest comes in the next record
  if (handshake_[1] != 0 || handshake_[2] != 0 || handshake_[3] != 1 || handshake_[4] > update_requested)
    return fail("a malformed KeyUpdate", decode_error);
  if (handshake_.size() != key_update_size) return fail("a KeyUpdate not at the end of its record", unexpected_message);
  // Our own KeyUpdate goes before the next application data (seal): one for however many
  // requests came while the server was silent.
  key_update_owed_ = key_update_owed_ || handshake_[4] == update_requested;
  handshake_.clear();
  receiving_.next_generation();
  return Status::done;
}

RecordLayer::Status RecordLayer::fail(std::string why, std::uint8_t alert) {
  const std::array<std::uint8_t, 2> fatal{alert_fatal, alert};
  sending_.seal(ContentType::alert, fatal, output_);  // tells the client why, if it reads on
  ended_ = Status::failed;
  error_ = std::move(why);
  return ended_;
}

void RecordLayer::write(std::span<const std::uint8_t> plaintext) {
  if (ended_ != Status::done) return;
  while (!plaintext.empty()) {
    const auto chunk = plaintext.first(std::min(plaintext.size(), max_record_plaintext));
    seal(ContentType::application_data, chunk);
    plaintext = plaintext.subspan(chunk.size());
  }
}

void RecordLayer::seal(ContentType type, std::span<const std::uint8_t> content) {
  if (key_update_owed_ || sending_.records() >= records_per_key_) {
    const std::array<std::uint8_t, key_update_size> update{key_update, 0, 0, 1, 0};  // not requested
    sending_.seal(ContentType::handshake, update, output_);
    sending_.next_generation();
    key_update_owed_ = false;
  }
  sending_.seal(type, content, output_);
}

void RecordLayer::take_output(std::vector<std::uint8_t>& out) {
  if (out.empty()) {
    out.swap(output_);
  } else {
    out.insert(out.end(), output_.begin(), output_.end());
  }
  output_.clear();
}

}  // namespace unima::tls
