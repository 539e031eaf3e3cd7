// unima-bench-propagation: how long a value takes to cross the bridge, both ways, against
// a running unima-bridged on the feed transport (SPEC §6).
//   feed -> Modbus: a telegram goes out on a feed connection; the time until a Modbus read
//                   of that register first returns the new value (reads back to back, so
//                   the resolution is one read round trip, reported too).
//   Modbus -> feed: a function 6 write into W; the time until the feed client has the
//                   change line (the bridge publishes before it answers the write).
// Every change carries a value different from the one before.

#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

#include "bench/bench_util.hpp"

namespace unima::bench {
namespace {

constexpr const char* usage =
    "usage: unima-bench-propagation --modbus-port N --feed-port N [--host 127.0.0.1]\n"
    "         [--changes 10000] [--warmup 100] [--device 5] [--offset 1] [--read-address 0x1101]\n"
    "         [--w-offset 0] [--write-address 0x3000] [--unit 1] [--json]\n"
    "  --device/--offset: the UnimaBUS address and register offset of the telegrams, which the\n"
    "  bridge serves at Modbus --read-address; --w-offset: the W register at --write-address.\n";

class LineReader {
 public:
  explicit LineReader(int fd) : fd_(fd) {}
  /// The next line without "\n"; throws at the deadline.
  std::string next(int timeout_ms) {
    const auto deadline = now_ns() + static_cast<std::uint64_t>(timeout_ms) * 1'000'000u;
    while (true) {
      if (const auto nl = buffered_.find('\n', scanned_); nl != std::string::npos) {
        std::string line = buffered_.substr(0, nl);
        buffered_.erase(0, nl + 1);
        scanned_ = 0;
        return line;
      }
      scanned_ = buffered_.size();
      const auto now = now_ns();
      if (now >= deadline) throw std::runtime_error("no feed line before the deadline");
      pollfd p{fd_, POLLIN, 0};
      if (::poll(&p, 1, static_cast<int>((deadline - now) / 1'000'000u) + 1) <= 0) continue;
      char chunk[4096];
      const auto n = ::recv(fd_, chunk, sizeof chunk, 0);
      if (n <= 0) throw std::runtime_error("the feed connection closed");
      buffered_.append(chunk, static_cast<std::size_t>(n));
    }
  }
  /// True when nothing more has arrived (and nothing is buffered).
  bool quiet() {
    pollfd p{fd_, POLLIN, 0};
    return buffered_.empty() && ::poll(&p, 1, 50) == 0;
  }

 private:
  int fd_;
  std::string buffered_;
  std::size_t scanned_ = 0;
};

struct Modbus {
  int fd;
  std::uint8_t unit;
  std::uint16_t transaction = 0;

  std::vector<std::uint8_t> adu(std::uint8_t function, std::uint16_t a, std::uint16_t b) {
    ++transaction;
    return {static_cast<std::uint8_t>(transaction >> 8), static_cast<std::uint8_t>(transaction), 0, 0, 0, 6, unit,
            function, static_cast<std::uint8_t>(a >> 8), static_cast<std::uint8_t>(a),
            static_cast<std::uint8_t>(b >> 8), static_cast<std::uint8_t>(b)};
  }
  std::vector<std::uint8_t> receive(std::size_t size) {
    std::vector<std::uint8_t> response(size);
    if (!receive_exactly(fd, response, 3000)) throw std::runtime_error("no Modbus response");
    if (response[0] != static_cast<std::uint8_t>(transaction >> 8) ||
        response[1] != static_cast<std::uint8_t>(transaction) || (response[7] & 0x80))
      throw std::runtime_error("unexpected Modbus response");
    return response;
  }
  std::uint16_t read_input(std::uint16_t address) {
    send_all(fd, adu(4, address, 1));
    const auto r = receive(11);
    return static_cast<std::uint16_t>(r[9] << 8 | r[10]);
  }
};

void print(const char* name, std::vector<std::uint32_t>& samples, bool json, bool last) {
  const auto p = percentiles(samples);
  if (json)
    std::printf("\"%s\":{\"p50_us\":%.2f,\"p99_us\":%.2f,\"p999_us\":%.2f,\"max_us\":%.2f}%s", name, p.p50, p.p99,
                p.p999, p.max, last ? "" : ",");
  else
    std::printf("%-16s p50 %.1f us  p99 %.1f us  p99.9 %.1f us  max %.1f us\n", name, p.p50, p.p99, p.p999, p.max);
}

int run(const Args& args) {
  const auto host = args.text("host");
  const auto changes = args.number("changes");
  const auto warmup = args.number("warmup");
  const auto device = args.number("device");
  const auto offset = args.number("offset");
  const auto read_address = static_cast<std::uint16_t>(args.number("read-address"));
  const auto w_offset = args.number("w-offset");
  const auto write_address = static_cast<std::uint16_t>(args.number("write-address"));

  const int feed_fd = connect_tcp(host, static_cast<std::uint16_t>(args.number("feed-port")));
  LineReader feed(feed_fd);
  // The snapshot ends with C+0x12 (SPEC §6).
  while (feed.next(5000).find(R"("bank":"C","offset":18,)") == std::string::npos) {
  }
  Modbus modbus{connect_tcp(host, static_cast<std::uint16_t>(args.number("modbus-port"))),
                static_cast<std::uint8_t>(args.number("unit"))};

  std::vector<std::uint32_t> feed_to_modbus, modbus_to_feed, read_rtt;
  const auto value_of = [](std::uint64_t i) { return static_cast<std::uint16_t>(1 + i % 30000); };
  for (std::uint64_t i = 0; i < warmup + changes; ++i) {
    const auto value = value_of(i);
    const std::string telegram = "{\"addr\":" + std::to_string(device) + ",\"slot\":0,\"offset\":" +
                                 std::to_string(offset) + ",\"values\":[" + std::to_string(value) + "]}\n";
    const auto sent = now_ns();
    send_all(feed_fd, std::span(reinterpret_cast<const std::uint8_t*>(telegram.data()), telegram.size()));
    std::uint64_t reads = 0;
    while (true) {
      const auto before = now_ns();
      const auto seen = modbus.read_input(read_address);
      const auto after = now_ns();
      if (i >= warmup) read_rtt.push_back(static_cast<std::uint32_t>(after - before));
      if (seen == value) {
        if (i >= warmup) feed_to_modbus.push_back(static_cast<std::uint32_t>(after - sent));
        break;
      }
      if (++reads > 100'000 || after - sent > 3'000'000'000u)
        throw std::runtime_error("telegram " + std::to_string(i) + " never became visible over Modbus");
    }
  }
  for (std::uint64_t i = 0; i < warmup + changes; ++i) {
    const auto value = value_of(i);
    const std::string expected = "{\"bank\":\"W\",\"offset\":" + std::to_string(w_offset) +
                                 ",\"value\":" + std::to_string(value) + "}";
    const auto sent = now_ns();
    send_all(modbus.fd, modbus.adu(6, write_address, value));
    const auto line = feed.next(3000);
    const auto arrived = now_ns();
    if (line != expected) throw std::runtime_error("feed line '" + line + "', expected '" + expected + "'");
    modbus.receive(12);
    if (i >= warmup) modbus_to_feed.push_back(static_cast<std::uint32_t>(arrived - sent));
  }
  if (!feed.quiet()) throw std::runtime_error("the feed sent more than the changes (an error line?)");
  ::close(modbus.fd);
  ::close(feed_fd);

  const bool json = args.flag("json");
  if (json) std::printf("{\"changes\":%llu,", static_cast<unsigned long long>(changes));
  print("feed_to_modbus", feed_to_modbus, json, false);
  print("modbus_to_feed", modbus_to_feed, json, false);
  print("read_round_trip", read_rtt, json, true);
  if (json) std::printf("}\n");
  return 0;
}

}  // namespace
}  // namespace unima::bench

int main(int argc, char** argv) {
  try {
    const unima::bench::Args args(argc, argv,
                                  {{"host", "127.0.0.1"}, {"modbus-port", ""}, {"feed-port", ""}, {"changes", "10000"},
                                   {"warmup", "100"}, {"device", "5"}, {"offset", "1"}, {"read-address", "0x1101"},
                                   {"w-offset", "0"}, {"write-address", "0x3000"}, {"unit", "1"}, {"json", "false"}},
                                  unima::bench::usage);
    if (args.text("modbus-port").empty() || args.text("feed-port").empty())
      throw std::runtime_error(std::string("--modbus-port and --feed-port are required\n") + unima::bench::usage);
    return unima::bench::run(args);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "unima-bench-propagation: %s\n", e.what());
    return 1;
  }
}
