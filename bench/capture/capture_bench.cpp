// capture_bench: how soon a capture block (MBS_RegC, seed 004 §7.1) publishes what it
// heard. The bench plays a third-party master and the foreign slave 3 on a pseudo-terminal
// whose other side the real daemon serves; each round writes register 0x0202 of device 3
// (function 6), and times from just before the write's last byte goes onto the line until
// a feed client (the UnimaBUS side) receives user output 1's new value. The daemon stores
// the value in C before it sends that line, so this is an upper bound of "shows up in C".
//
// Usage: capture_bench [--count N] [--baud B] [--enforce]
// Prints the distribution and the budget (one frame time + 1 ms); --enforce exits 2 when
// the 99th percentile is over it. Exits 1 when it cannot measure.

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <poll.h>
#include <pty.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <termios.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "tests/support/child_process.hpp"
#include "tests/support/pseudo_terminal.hpp"
#include "modbus/rtu/rtu_adu.hpp"
#include "modbus/rtu/rtu_timing.hpp"

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using namespace std::chrono_literals;

[[noreturn]] void fail(const std::string& why) {
  std::fprintf(stderr, "capture_bench: %s\n", why.c_str());
  std::exit(1);
}

bool eventually(const auto& condition, std::chrono::milliseconds timeout) {
  const auto deadline = Clock::now() + timeout;
  while (!condition()) {
    if (Clock::now() >= deadline) return false;
    std::this_thread::sleep_for(5ms);
  }
  return true;
}

std::uint16_t free_port() {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (::bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) fail("bind");
  socklen_t len = sizeof addr;
  ::getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &len);
  ::close(fd);
  return ntohs(addr.sin_port);
}

struct TempDir {
  fs::path path;
  TempDir() {
    std::string pattern = (fs::temp_directory_path() / "unima-capture-bench-XXXXXX").string();
    if (!::mkdtemp(pattern.data())) fail("mkdtemp");
    path = pattern;
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
};

// The bench's end of the line: the master side of a raw pseudo-terminal.
struct Line {
  int master = -1;
  int slave = -1;
  explicit Line(const fs::path& link) {
    const auto pty = unima::test_support::open_raw_pseudo_terminal();
    master = pty.master;
    slave = pty.slave;
    unima::test_support::point_link_at(link, pty.name);
  }
  ~Line() {
    ::close(master);
    ::close(slave);
  }
  void write(const std::vector<std::uint8_t>& bytes) const {
    if (::write(master, bytes.data(), bytes.size()) != static_cast<ssize_t>(bytes.size())) fail("write to the line");
  }
  // The bridge must not answer a foreign write; whatever it sends is a failure.
  bool quiet() const {
    pollfd p{master, POLLIN, 0};
    return ::poll(&p, 1, 0) == 0;
  }
};

struct Daemon {
  fs::path log;
  unima::test_support::ChildProcess process;
  Daemon(const fs::path& config, const fs::path& log_path)
      : log(log_path), process({UNIMA_BRIDGED, "--config", config.string()}, unima::test_support::stopped_by_sigterm(log_path)) {}
  std::string text() const {
    std::ifstream in(log);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
  }
};

// A feed client: the UnimaBUS side, where user outputs are published.
struct Feed {
  int fd = -1;
  std::string buffered;
  explicit Feed(std::uint16_t port) {
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_port = htons(port);
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    const bool connected = eventually(
        [&] {
          fd = ::socket(AF_INET, SOCK_STREAM, 0);
          if (::connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) == 0) return true;
          ::close(fd);
          return false;
        },
        10s);
    if (!connected) fail("the daemon's feed port never accepted");
  }
  ~Feed() { ::close(fd); }
  // Lines until one equals `line`; false at the deadline.
  bool wait_for(const std::string& line, std::chrono::milliseconds timeout) {
    const auto deadline = Clock::now() + timeout;
    while (true) {
      for (auto newline = buffered.find('\n'); newline != std::string::npos; newline = buffered.find('\n')) {
        const bool match = buffered.compare(0, newline, line) == 0 && newline == line.size();
        buffered.erase(0, newline + 1);
        if (match) return true;
      }
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count();
      if (left <= 0) return false;
      pollfd p{fd, POLLIN, 0};
      if (::poll(&p, 1, static_cast<int>(left)) <= 0) return false;
      char buf[4096];
      const auto got = ::recv(fd, buf, sizeof buf, 0);
      if (got <= 0) return false;
      buffered.append(buf, static_cast<std::size_t>(got));
    }
  }
};

std::vector<std::uint8_t> foreign_write(std::uint16_t value) {
  const std::vector<std::uint8_t> pdu = {0x06, 0x02, 0x02, static_cast<std::uint8_t>(value >> 8),
                                         static_cast<std::uint8_t>(value)};
  std::vector<std::uint8_t> adu(pdu.size() + 3);
  unima::modbus::write_rtu_adu(3, pdu, adu);
  return adu;
}

double percentile(const std::vector<double>& sorted, double p) {
  const auto rank = static_cast<std::size_t>(std::ceil(p / 100.0 * static_cast<double>(sorted.size())));
  return sorted[std::clamp<std::size_t>(rank, 1, sorted.size()) - 1];
}

}  // namespace

int main(int argc, char** argv) {
  int count = 1000;
  unsigned baud = 19200;
  bool enforce = false;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--count" && i + 1 < argc) count = std::atoi(argv[++i]);
    else if (arg == "--baud" && i + 1 < argc) baud = static_cast<unsigned>(std::atoi(argv[++i]));
    else if (arg == "--enforce") enforce = true;
    else fail("usage: capture_bench [--count N] [--baud B] [--enforce]");
  }
  if (count < 1 || count > 60000) fail("--count must be 1..60000");

  TempDir dir;
  Line line(dir.path / "ttyRTU");
  const auto feed_port = free_port();
  const auto tcp_port = free_port();
  {
    std::ofstream config(dir.path / "bridge.yaml");
    config << "unimabus: { address: 5, transport: feed, listen: 127.0.0.1:" << feed_port << " }\n"
           << "modbus:\n  address: 1\n  tcp: { listen: 127.0.0.1, port: " << tcp_port << " }\n"
           << "  rtu: { device: " << (dir.path / "ttyRTU").string() << ", baud: " << baud << " }\n"
           << "blocks:\n  - { type: capture, device: 3, register: 0x0202, output: 1 }\n"
           << "status: { socket: " << (dir.path / "control.sock").string() << " }\n";
  }
  Daemon daemon(dir.path / "bridge.yaml", dir.path / "daemon.log");
  Feed feed(feed_port);
  if (!feed.wait_for(R"({"bank":"C","offset":18,"value":0})", 5s)) fail("no feed snapshot\n" + daemon.text());
  if (!eventually([&] { return daemon.text().find("modbus rtu: serving") != std::string::npos; }, 5s))
    fail("the daemon never opened the line\n" + daemon.text());

  const auto timing = unima::modbus::rtu_timing(baud, false, 1);
  const auto frame_time = timing.character * 8;
  const double budget_us = static_cast<double>((frame_time + std::chrono::milliseconds(1)).count());

  constexpr int warm_up = 20;
  std::vector<double> latencies_us;
  latencies_us.reserve(static_cast<std::size_t>(count));
  for (int i = 0; i < warm_up + count; ++i) {
    const auto value = static_cast<std::uint16_t>(1000 + i);
    const auto frame = foreign_write(value);
    const auto expected = R"({"bank":"C","offset":0,"value":)" + std::to_string(value) + "}";
    const auto before = Clock::now();
    line.write(frame);
    if (!feed.wait_for(expected, 2s)) fail("capture " + std::to_string(i) + " never arrived\n" + daemon.text());
    const auto after = Clock::now();
    if (!line.quiet()) fail("the bridge answered a foreign write");
    line.write(frame);  // slave 3 echoes the write, as a real one would
    if (i >= warm_up)
      latencies_us.push_back(std::chrono::duration<double, std::micro>(after - before).count());
  }

  std::sort(latencies_us.begin(), latencies_us.end());
  double sum = 0;
  for (double v : latencies_us) sum += v;
  const auto within = std::count_if(latencies_us.begin(), latencies_us.end(), [&](double v) { return v <= budget_us; });
  const double p99 = percentile(latencies_us, 99);
  std::printf("capture latency, %d foreign writes (fn 6, 8 bytes) at %u baud on a pty, write -> feed line:\n", count, baud);
  std::printf("  min %.0f us  p50 %.0f us  p90 %.0f us  p99 %.0f us  max %.0f us  mean %.0f us\n", latencies_us.front(),
              percentile(latencies_us, 50), percentile(latencies_us, 90), p99, latencies_us.back(),
              sum / static_cast<double>(latencies_us.size()));
  std::printf("  budget: one frame (%lld us) + 1 ms = %.0f us; within budget: %ld of %d; p99 %s\n",
              static_cast<long long>(frame_time.count()), budget_us, static_cast<long>(within), count,
              p99 <= budget_us ? "within" : "OVER");
  return enforce && p99 > budget_us ? 2 : 0;
}
