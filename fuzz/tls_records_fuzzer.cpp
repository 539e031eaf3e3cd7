// Fuzz target: what a TLS 1.3 client sends the Modbus/TCP Security port after its handshake
// (SPEC §11), read by tls::RecordLayer. The records are sealed under the client's key as a
// real client would, so the fuzzer reaches behind the AEAD: application data, KeyUpdates
// that ask or not, alerts, padding, empty records, unknown inner types, and bytes that are
// no record at all; cut into pieces anywhere.
//
// A client that sends more records in a row without data than RecordLayer allows is
// treated as one that misbehaves: what it sent arrives up to there.
//
// Input: a script. Each step is one byte `op` and, for the steps that carry content, one
// byte `n` and n bytes: op % 8 == 0 application data, 1 a handshake message (a KeyUpdate
// when the content is one, and then the client's key moves on), 2 an alert, 3 raw bytes,
// 4 application data padded with `op / 8 + 1` zeros, 5 an empty record of an inner type n,
// 6 the next piece the server is fed ends here, 7 the server answers `n` bytes.

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "fuzz/fuzz_check.hpp"
#include "tls/record_layer.hpp"

namespace {

using namespace unima::tls;
using Bytes = std::vector<std::uint8_t>;
using Status = RecordLayer::Status;

const Bytes client_secret(32, 0x5a);
const Bytes server_secret(32, 0xa5);

// Everything the server lets through, until it stops.
Status read_all(RecordLayer& layer, std::string& text) {
  std::uint8_t buffer[97];  // an odd size: plaintext comes out in pieces
  std::size_t n = 0;
  Status status{};
  while ((status = layer.read(buffer, n)) == Status::done) text.append(reinterpret_cast<char*>(buffer), n);
  FUZZ_CHECK(n == 0);
  return status;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  RecordLayer server(0x1301, client_secret, server_secret, 5);
  RecordLayer mirror(0x1301, server_secret, client_secret);  // reads what the server sends
  TrafficProtection client(0x1301, client_secret, true);

  Bytes piece;
  std::string read, expected, answered, mirror_read;
  bool only_data = true;  // nothing but application data sealed as a client would
  int records_without_data = 0;  // in a row: more than RecordLayer allows is a flood
  const auto count_record = [&](bool data) {
    records_without_data = data ? 0 : records_without_data + 1;
    if (records_without_data > RecordLayer::max_records_without_data) only_data = false;
  };
  Status status = Status::want_input;
  const auto feed_piece = [&] {
    server.feed(piece);
    piece.clear();
    status = read_all(server, read);
  };

  std::size_t at = 0;
  while (at < size) {
    const std::uint8_t op = data[at++];
    const std::size_t n = at < size ? data[at++] : 0;
    const auto content = std::span(data + at, std::min(n, size - at));
    if (op % 8 <= 4) at += content.size();
    switch (op % 8) {
      case 0:
        client.seal(ContentType::application_data, content, piece);
        expected.append(content.begin(), content.end());
        count_record(!content.empty());
        break;
      case 1:
        client.seal(ContentType::handshake, content, piece);
        if (content.size() == 5 && content[0] == 24 && content[1] == 0 && content[2] == 0 && content[3] == 1 &&
            content[4] <= 1)
          client.next_generation();
        only_data = false;
        break;
      case 2:
        client.seal(ContentType::alert, content, piece);
        only_data = false;
        break;
      case 3:
        piece.insert(piece.end(), content.begin(), content.end());
        only_data = only_data && content.empty();
        break;
      case 4: {
        // Sealed as inner type 0, the content, its type and the zeros make a padded record.
        Bytes padded(content.begin(), content.end());
        padded.push_back(static_cast<std::uint8_t>(ContentType::application_data));
        padded.resize(padded.size() + op / 8, 0);
        client.seal(static_cast<ContentType>(0), padded, piece);
        expected.append(content.begin(), content.end());
        count_record(!content.empty());
        break;
      }
      case 5:
        client.seal(static_cast<ContentType>(n), {}, piece);
        only_data = only_data && n == static_cast<std::size_t>(ContentType::application_data);
        count_record(false);
        break;
      case 6:
        feed_piece();
        break;
      case 7: {
        const Bytes answer(n, static_cast<std::uint8_t>(op));
        server.write(answer);
        if (status != Status::failed && status != Status::closed) answered.append(answer.begin(), answer.end());
        break;
      }
    }
  }
  feed_piece();

  // Once over, over: nothing more is read, whatever comes.
  if (status == Status::failed || status == Status::closed) {
    server.feed(Bytes(40, 0x17));
    std::string after;
    FUZZ_CHECK(read_all(server, after) == status && after.empty());
    FUZZ_CHECK((status == Status::failed) == !server.error().empty());
  }
  // What a well-behaved client sent arrives whole and in order.
  if (only_data) {
    FUZZ_CHECK(status == Status::want_input);
    FUZZ_CHECK(read == expected);
  } else {
    FUZZ_CHECK(expected.compare(0, read.size(), read) == 0);
  }
  // The server's own records (answers, its KeyUpdates every 5 records, a fatal alert) are
  // TLS its peer reads: the answers in order, then at most the alert.
  Bytes wire;
  server.take_output(wire);
  mirror.feed(wire);
  const auto mirror_status = read_all(mirror, mirror_read);
  FUZZ_CHECK(mirror_read == answered);
  FUZZ_CHECK(mirror_status == (status == Status::failed && !server.error().starts_with("the client sent")
                                   ? Status::failed
                                   : Status::want_input));
  return 0;
}
