// The TCP slave when the client does not keep up: the answers of a read go out in one
// non-blocking send, and what does not fit waits for the socket (SPEC §3: pipelined
// requests are answered in order, nothing lost).

#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include "tests/integration/bridge_fixture.hpp"

namespace unima::test {
namespace {

class Backpressure : public BridgeTest {};

TEST_F(Backpressure, AClientThatReadsLateGetsEveryAnswerInOrder) {
  // D1 and D2 back to back: 128 registers, so a read can take the most a response holds.
  config.banks = "{ D1: 0x6000, D2: 0x6040 }";
  config.devices = "{ D1: { type: unigen-chp, address: 5 }, D2: { type: unigen-chp, address: 6 } }";
  start();
  // A small receive buffer on the client, which reads nothing until it has sent all it
  // can and then reads the first 2 MB 16 bytes at a time: the bridge answers some 20 times
  // faster than that drains, and a loopback send buffer holds at most 4 MiB, so its
  // answers have to wait for the socket long before the 25 MB of them are through.
  const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
  const int small = 4096;
  ASSERT_EQ(::setsockopt(fd, SOL_SOCKET, SO_RCVBUF, &small, sizeof small), 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(config.modbus_port);
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  ::connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr);  // EINPROGRESS: POLLOUT says when
  pollfd connecting{fd, POLLOUT, 0};
  ASSERT_EQ(::poll(&connecting, 1, 5000), 1);

  constexpr std::size_t requests = 100'000;
  constexpr std::size_t answer_size = 9 + 2 * 123;  // the most registers a read may ask for
  Bytes batch;
  batch.reserve(requests * 12);
  for (std::size_t t = 0; t < requests; ++t) {
    const Bytes q = {static_cast<std::uint8_t>(t >> 8), static_cast<std::uint8_t>(t), 0, 0, 0, 6, 1, 0x04, 0x60, 0x00,
                     0x00, 123};
    batch.insert(batch.end(), q.begin(), q.end());
  }
  std::size_t sent = 0;
  const auto send_more = [&] {
    while (sent < batch.size()) {
      const auto n = ::send(fd, batch.data() + sent, batch.size() - sent, MSG_NOSIGNAL);
      if (n <= 0) return;
      sent += static_cast<std::size_t>(n);
    }
  };
  send_more();

  Bytes answers;
  answers.reserve(requests * answer_size);
  const auto deadline = std::chrono::steady_clock::now() + 60s;
  while (answers.size() < requests * answer_size && std::chrono::steady_clock::now() < deadline) {
    pollfd p{fd, static_cast<short>(POLLIN | (sent < batch.size() ? POLLOUT : 0)), 0};
    if (::poll(&p, 1, 1000) <= 0) continue;
    if (p.revents & POLLOUT) send_more();
    std::uint8_t chunk[65536];
    const std::size_t slowly = 2'000'000;
    const auto n = ::recv(fd, chunk, answers.size() < slowly ? 16 : sizeof chunk, 0);
    if (n == 0) break;
    if (n > 0) answers.insert(answers.end(), chunk, chunk + n);
  }
  ::close(fd);

  ASSERT_EQ(answers.size(), requests * answer_size);
  for (std::size_t t = 0; t < requests; ++t) {
    const auto* a = answers.data() + t * answer_size;
    ASSERT_EQ((Bytes{a, a + 9}), (Bytes{static_cast<std::uint8_t>(t >> 8), static_cast<std::uint8_t>(t), 0, 0, 0,
                                        answer_size - 6, 1, 0x04, 2 * 123}))
        << "answer " << t;
  }
}

}  // namespace
}  // namespace unima::test
