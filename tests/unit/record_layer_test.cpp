// tls::RecordLayer, the TLS 1.3 records after the handshake (RFC 8446 §5, §4.6.3, §6), against
// its mirror — a layer with the two secrets swapped reads what the server seals, and
// TrafficProtection seals by hand what a client might send. Interworking with a real client
// is memory_session_test's (OpenSSL's) and the integration tests' (Python's ssl).

#include <gtest/gtest.h>

#include <array>
#include <string>
#include <vector>

#include "tls/record_layer.hpp"

namespace unima::tls {
namespace {

using Status = RecordLayer::Status;
using Bytes = std::vector<std::uint8_t>;

constexpr std::uint16_t aes_128_gcm_sha256 = 0x1301;
const Bytes client_secret(32, 0x11);
const Bytes server_secret(32, 0x22);

std::span<const std::uint8_t> bytes_of(const std::string& text) {
  return std::span(reinterpret_cast<const std::uint8_t*>(text.data()), text.size());
}

std::string read_all(RecordLayer& layer, Status& last) {
  std::string text;
  std::array<std::uint8_t, 64> buffer{};
  std::size_t n = 0;
  while ((last = layer.read(buffer, n)) == Status::done) text.append(reinterpret_cast<char*>(buffer.data()), n);
  return text;
}

std::size_t records_in(const Bytes& stream) {
  std::size_t count = 0;
  for (std::size_t at = 0; at + record_header_size <= stream.size(); ++count)
    at += record_header_size + (std::size_t{stream[at + 3]} << 8 | stream[at + 4]);
  return count;
}

// What a client sends: records sealed under the client's secret.
struct Client {
  TrafficProtection sealing{aes_128_gcm_sha256, client_secret, true};
  Bytes wire;
  void send(ContentType type, const Bytes& content) { sealing.seal(type, content, wire); }
};

TEST(RecordLayer, ItsRecordsAreReadByItsMirrorAndAKeyUpdateComesBeforeTheLimit) {
  RecordLayer server(aes_128_gcm_sha256, client_secret, server_secret, 3);
  RecordLayer mirror(aes_128_gcm_sha256, server_secret, client_secret);
  std::string expected;
  for (int i = 0; i < 10; ++i) {
    const auto text = "answer " + std::to_string(i) + ";";
    server.write(bytes_of(text));
    expected += text;
  }
  Bytes wire;
  server.take_output(wire);
  EXPECT_FALSE(server.has_output());
  EXPECT_EQ(records_in(wire), 13U);  // ten answers, a KeyUpdate after every three
  mirror.feed(wire);
  Status last{};
  EXPECT_EQ(read_all(mirror, last), expected);
  EXPECT_EQ(last, Status::want_input);
}

TEST(RecordLayer, AClientsRecordsSplitAndJoinedAnywhereAreReadInOrder) {
  RecordLayer server(aes_128_gcm_sha256, client_secret, server_secret);
  Client client;
  client.send(ContentType::application_data, Bytes{'a', 'b'});
  client.send(ContentType::application_data, Bytes{});  // an empty record is allowed
  client.send(ContentType::application_data, Bytes{'c'});
  std::string text;
  for (const auto byte : client.wire) {
    server.feed(std::span(&byte, 1));
    Status last{};
    text += read_all(server, last);
    ASSERT_EQ(last, Status::want_input);
  }
  EXPECT_EQ(text, "abc");
}

// RFC 8446 §4.6.3: requests that come while the server is silent get one KeyUpdate.
TEST(RecordLayer, KeyUpdatesThatAskForOneAreAnsweredOnceBeforeTheNextAnswer) {
  RecordLayer server(aes_128_gcm_sha256, client_secret, server_secret);
  RecordLayer mirror(aes_128_gcm_sha256, server_secret, client_secret);
  Client client;
  for (int i = 0; i < 3; ++i) {
    client.send(ContentType::handshake, Bytes{24, 0, 0, 1, 1});
    client.sealing.next_generation();
  }
  client.send(ContentType::application_data, Bytes{'x'});
  server.feed(client.wire);
  Status last{};
  EXPECT_EQ(read_all(server, last), "x");
  server.write(bytes_of("y"));
  Bytes wire;
  server.take_output(wire);
  EXPECT_EQ(records_in(wire), 2U);  // one KeyUpdate, then the answer under the next key
  mirror.feed(wire);
  EXPECT_EQ(read_all(mirror, last), "y");
}

// Each KeyUpdate costs a key derivation: a client may not ask for them without end.
TEST(RecordLayer, SixteenRecordsWithoutDataInARowAreAllowedAndTheSeventeenthIsAFlood) {
  const auto after = [](int updates) {
    RecordLayer server(aes_128_gcm_sha256, client_secret, server_secret);
    Client client;
    for (int i = 0; i < updates; ++i) {
      client.send(ContentType::handshake, Bytes{24, 0, 0, 1, 1});
      client.sealing.next_generation();
    }
    client.send(ContentType::application_data, Bytes{'d'});
    server.feed(client.wire);
    Status last{};
    const auto text = read_all(server, last);
    return text == "d" ? std::string("served") : server.error();
  };
  EXPECT_EQ(after(16), "served");
  EXPECT_EQ(after(17), "more than 16 records in a row without data");
}

struct Refusal {
  const char* what;
  ContentType type;
  Bytes content;
};

class RecordLayerRefuses : public ::testing::TestWithParam<Refusal> {};

TEST_P(RecordLayerRefuses, WhatAClientMustNotSendAfterTheHandshake) {
  RecordLayer server(aes_128_gcm_sha256, client_secret, server_secret);
  Client client;
  client.send(GetParam().type, GetParam().content);
  client.send(ContentType::application_data, Bytes{'w'});
  server.feed(client.wire);
  Status last{};
  EXPECT_EQ(read_all(server, last), "");
  EXPECT_EQ(last, Status::failed);
  EXPECT_FALSE(server.error().empty());
  std::size_t n = 0;
  std::array<std::uint8_t, 4> buffer{};
  EXPECT_EQ(server.read(buffer, n), Status::failed) << "failed stays failed";
}

INSTANTIATE_TEST_SUITE_P(
    Messages, RecordLayerRefuses,
    ::testing::Values(Refusal{"NewSessionTicket", ContentType::handshake, Bytes{4, 0, 0, 1, 0}},
                      Refusal{"ClientHello", ContentType::handshake, Bytes{1, 0, 0, 0}},
                      Refusal{"KeyUpdate of length 2", ContentType::handshake, Bytes{24, 0, 0, 2, 0, 0}},
                      Refusal{"KeyUpdate asking 2", ContentType::handshake, Bytes{24, 0, 0, 1, 2}},
                      Refusal{"KeyUpdate then more", ContentType::handshake, Bytes{24, 0, 0, 1, 0, 24}},
                      Refusal{"KeyUpdate cut by data", ContentType::handshake, Bytes{24, 0}},
                      Refusal{"empty handshake record", ContentType::handshake, Bytes{}},
                      Refusal{"fatal alert", ContentType::alert, Bytes{2, 40}},
                      Refusal{"alert of 3 bytes", ContentType::alert, Bytes{1, 0, 0}},
                      Refusal{"inner change_cipher_spec", static_cast<ContentType>(20), Bytes{1}}),
    [](const auto& info) {
      std::string name;
      for (const char c : std::string(info.param.what))
        if (std::isalnum(static_cast<unsigned char>(c))) name += c;
      return name;
    });

TEST(RecordLayer, CloseNotifyClosesAndUserCanceledDoesNot) {
  RecordLayer server(aes_128_gcm_sha256, client_secret, server_secret);
  Client client;
  client.send(ContentType::application_data, Bytes{'a'});
  client.send(ContentType::alert, Bytes{1, 90});
  client.send(ContentType::application_data, Bytes{'b'});
  client.send(ContentType::alert, Bytes{1, 0});
  server.feed(client.wire);
  Status last{};
  EXPECT_EQ(read_all(server, last), "ab");
  EXPECT_EQ(last, Status::closed);
}

TEST(RecordLayer, ForgedTooLongAndUnprotectedRecordsFailWithAnAlertForTheClient) {
  const auto fails = [](Bytes wire) {
    RecordLayer server(aes_128_gcm_sha256, client_secret, server_secret);
    RecordLayer mirror(aes_128_gcm_sha256, server_secret, client_secret);
    server.feed(wire);
    Status last{};
    read_all(server, last);
    Bytes alert;
    server.take_output(alert);
    mirror.feed(alert);
    Status client_saw{};
    read_all(mirror, client_saw);
    return last == Status::failed && client_saw == Status::failed && mirror.error().find("alert") != std::string::npos;
  };
  Client client;
  client.send(ContentType::application_data, Bytes{'w'});
  auto forged = client.wire;
  forged[record_header_size] ^= 0x80;
  EXPECT_TRUE(fails(forged));
  EXPECT_TRUE(fails(Bytes{23, 3, 3, 0x42, 0x01}));              // longer than 2^14 + 256: refused from its header
  EXPECT_TRUE(fails(Bytes{22, 3, 3, 0, 4, 1, 0, 0, 0}));        // a handshake record in the clear
  EXPECT_TRUE(fails(Bytes{20, 3, 3, 0, 1, 1}));                 // change_cipher_spec after the handshake
  EXPECT_TRUE(fails(Bytes{23, 3, 3, 0, 3, 1, 2, 3}));           // shorter than a tag
  RecordLayer unread(aes_128_gcm_sha256, client_secret, server_secret);
  unread.feed(Bytes{23, 3, 3, 0x41, 0x00});                     // 2^14 + 256 exactly: waits for its body
  Status last{};
  read_all(unread, last);
  EXPECT_EQ(last, Status::want_input);
}

TEST(TrafficProtection, ProtectsTheThreeTls13SuitesAndRefusesAnyOther) {
  for (const std::uint16_t suite : {0x1301, 0x1302, 0x1303}) {
    const Bytes secret(suite == 0x1302 ? 48 : 32, 0x33);
    TrafficProtection sealing(suite, secret, true);
    TrafficProtection opening(suite, secret, false);
    Bytes wire;
    sealing.seal(ContentType::application_data, Bytes{'o', 'k'}, wire);
    const auto opened = opening.open(wire);
    ASSERT_TRUE(opened.has_value()) << suite;
    EXPECT_EQ(std::string(opened->content.begin(), opened->content.end()), "ok");
    EXPECT_EQ(opening.records(), 1U);
  }
  EXPECT_FALSE(TrafficProtection::protects(0x1304));  // TLS_AES_128_CCM_SHA256
  EXPECT_THROW(TrafficProtection(0xc02b, Bytes(32, 0), true), std::runtime_error);
  EXPECT_THROW(TrafficProtection(0x1302, Bytes(32, 0), true), std::runtime_error) << "SHA-384's secret is 48 bytes";
}

}  // namespace
}  // namespace unima::tls
