#pragma once
// Issue 29's handshake flood, as the tests of both TLS ports play it: one ClientHello of
// OpenSSL's client, replayed from 127.0.0.2 (a host apart from the test's other clients;
// Linux routes all of 127/8 on lo) on rounds of new connections.

#include <openssl/ssl.h>

#include <chrono>
#include <cstdint>
#include <functional>
#include <vector>

#include "tests/support/loopback.hpp"
#include "tests/support/peers/memory_tls_client.hpp"

namespace unima::test {

/// The first flight of a fresh OpenSSL client.
inline std::vector<std::uint8_t> a_client_hello() {
  SSL_CTX* context = SSL_CTX_new(TLS_client_method());
  std::vector<std::uint8_t> hello;
  {
    test_support::MemoryTlsClient client(context);
    SSL_do_handshake(client.ssl());
    hello = client.take_output();
  }
  SSL_CTX_free(context);
  return hello;
}

struct HandshakeFlood {
  int answered = 0;  // connections the server answered with its first flight: handshakes it did
  int closed = 0;    // connections it closed unanswered
  bool connected = true;
};

/// `rounds` rounds of 8 connections from 127.0.0.2 to `port` at once, each sending `hello`
/// and reading the server's first bytes or its end; `after_round(round)` between rounds.
inline HandshakeFlood replay_client_hello(std::uint16_t port, const std::vector<std::uint8_t>& hello, int rounds,
                                          const std::function<void(int round)>& after_round) {
  using namespace std::chrono_literals;
  HandshakeFlood flood;
  for (int round = 0; round < rounds; ++round) {
    std::vector<test_support::Socket> sockets;
    for (int i = 0; i < 8; ++i) {
      sockets.push_back(test_support::Socket::tcp_from("127.0.0.2", port));
      if (!sockets.back().valid()) flood.connected = false;
      sockets.back().send(hello);
    }
    for (auto& socket : sockets) {
      const auto reply = socket.receive(5, 2000ms);
      if (reply.size() == 5 && reply[0] == 0x16) ++flood.answered;
      else ++flood.closed;
    }
    after_round(round);
  }
  return flood;
}

}  // namespace unima::test
