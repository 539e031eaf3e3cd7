// unima-bench-libmodbus-server: the reference an integrator would write on libmodbus's
// public API — the classic select loop of libmodbus's own examples (pselect, for a clean stop), one modbus_mapping,
// modbus_receive + modbus_reply per readable client. It serves the same registers as the
// bench's bridge config (input and holding registers at --address, --count of them), so
// both servers answer the same requests with responses of the same size.

#include <modbus/modbus.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/select.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <string>

#include "bench/bench_util.hpp"

namespace {

constexpr const char* usage =
    "usage: unima-bench-libmodbus-server --port N [--listen 127.0.0.1] [--address 0x1100] [--count 64]\n";

volatile std::sig_atomic_t stop_requested = 0;
void request_stop(int) { stop_requested = 1; }

}  // namespace

int main(int argc, char** argv) {
  try {
    const unima::bench::Args args(argc, argv, {{"listen", "127.0.0.1"}, {"port", ""}, {"address", "0x1100"}, {"count", "64"}},
                                  usage);
    if (args.text("port").empty()) throw std::runtime_error(std::string("--port is required\n") + usage);
    const auto address = static_cast<unsigned>(args.number("address"));
    const auto count = static_cast<unsigned>(args.number("count"));

    // SIGTERM ends the loop so that valgrind and strace see a normal exit. The signals stay
    // blocked except inside pselect(), which unblocks them atomically: a SIGTERM between the
    // loop's test and the wait would otherwise leave select() blocked for good once the
    // clients are gone (it did, under strace, in a CI run). glibc's select() is the same
    // pselect6 system call, so the counts the bench compares do not change.
    struct sigaction action {};
    action.sa_handler = request_stop;
    sigaction(SIGTERM, &action, nullptr);
    sigaction(SIGINT, &action, nullptr);
    sigset_t stop_signals, while_waiting;
    sigemptyset(&stop_signals);
    sigaddset(&stop_signals, SIGTERM);
    sigaddset(&stop_signals, SIGINT);
    sigprocmask(SIG_BLOCK, &stop_signals, &while_waiting);

    modbus_t* ctx = modbus_new_tcp(args.text("listen").c_str(), static_cast<int>(args.number("port")));
    if (!ctx) throw std::runtime_error(std::string("modbus_new_tcp: ") + modbus_strerror(errno));
    modbus_mapping_t* mapping = modbus_mapping_new_start_address(0, 0, 0, 0, address, count, address, count);
    if (!mapping) throw std::runtime_error(std::string("modbus_mapping_new: ") + modbus_strerror(errno));
    for (unsigned i = 0; i < count; ++i) {
      mapping->tab_input_registers[i] = static_cast<std::uint16_t>(0x7FFF - i);
      mapping->tab_registers[i] = static_cast<std::uint16_t>(i);
    }
    const int server = modbus_tcp_listen(ctx, 128);
    if (server < 0) throw std::runtime_error(std::string("modbus_tcp_listen: ") + modbus_strerror(errno));

    fd_set clients;
    FD_ZERO(&clients);
    FD_SET(server, &clients);
    int highest = server;
    std::uint8_t query[MODBUS_TCP_MAX_ADU_LENGTH];
    while (!stop_requested) {
      fd_set readable = clients;
      if (pselect(highest + 1, &readable, nullptr, nullptr, nullptr, &while_waiting) < 0) {
        if (errno == EINTR) continue;
        throw std::runtime_error(std::string("pselect: ") + std::strerror(errno));
      }
      for (int fd = 0; fd <= highest; ++fd) {
        if (!FD_ISSET(fd, &readable)) continue;
        if (fd == server) {
          const int client = accept(server, nullptr, nullptr);
          if (client < 0) continue;
          if (client >= FD_SETSIZE) {
            close(client);
            continue;
          }
          // The example leaves Nagle's algorithm on; with pipelined requests its separate
          // replies then wait for the client's delayed ACK (40 ms). The bridge sets
          // TCP_NODELAY, so the reference does too: the comparison is of the servers.
          const int one = 1;
          setsockopt(client, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
          FD_SET(client, &clients);
          if (client > highest) highest = client;
          continue;
        }
        modbus_set_socket(ctx, fd);
        const int rc = modbus_receive(ctx, query);
        if (rc > 0) {
          modbus_reply(ctx, query, rc, mapping);
        } else if (rc == -1) {
          close(fd);
          FD_CLR(fd, &clients);
          while (highest > server && !FD_ISSET(highest, &clients)) --highest;
        }
      }
    }
    for (int fd = 0; fd <= highest; ++fd)
      if (FD_ISSET(fd, &clients)) close(fd);
    modbus_mapping_free(mapping);
    modbus_free(ctx);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "unima-bench-libmodbus-server: %s\n", e.what());
    return 1;
  }
}
