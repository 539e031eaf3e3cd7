// gateway_bench: how well the gateway (SPEC §14, issue 31) uses and shares the RTU line.
//
// The daemon in master mode forwards Modbus TCP requests for unit 5 to foreign-slave-sim
// on a pseudo-terminal; the simulator plays the wire of a line at the configured baud
// (its --baud: an answer leaves when the request, the slave's t3.5, its 1 ms answer delay
// and the answer itself would have taken that long) and logs every frame with its time.
// Every request is a read of D0..D9 (function 3, 10 registers: an 8-byte query, a 25-byte
// answer). Measured, in paired rounds (each round runs every configuration once, one after
// the other, so both halves of a pair see the same machine):
//
//   line use   8 clients asking without pause, at 19200 and 115200 baud: forwarded
//              transactions per second against the line's limit, 1 ÷ ((query + answer
//              bytes) × 10 bits ÷ baud + 2 × t3.5 + the slave's answer delay)
//   fairness   the same runs: each client's count against the mean of the 8
//   priority   a priority peer (127.0.0.2) asking at random moments among the 8: its p99
//              latency against one transaction in progress + its own
//   overhead   one client on an idle line: its latency minus the line time of its
//              transaction (request heard to answer ended, in the frame log), p99
//   banks      the daemon's own banks (function 4) under unima-bench-load, with the
//              gateway idle and with the 8 clients busy on it; and, steadier on a shared
//              host, the gateway process's CPU time per forwarded transaction
//   mbusd      with --mbusd PATH, the line-use and fairness runs through mbusd too
//
// With --lines, the runs of several lines from one daemon instead (lines_bench.cpp).
//
// Beside them, how late this host wakes a sleeping thread: the latencies' tails are that.
//
// Every load loop is bounded by time and by count. Exit 0 when every run worked and every
// answer was right, 1 otherwise, 2 when it could not start; no time is asserted — each
// target is printed as met or missed beside its figure (docs/performance.md, Gateway).

#include "bench/gateway/gateway_bench.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <signal.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "modbus/rtu/rtu_timing.hpp"
#include "tests/support/child_process.hpp"

namespace gateway_bench {

namespace fs = std::filesystem;
using unima::test_support::ChildProcess;

namespace {

constexpr std::uint8_t unit = 5;
const char* const priority_address = "127.0.0.2";

int connect_to(std::uint16_t port, const char* from = nullptr) {
  const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  const int one = 1;
  ::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
  const timeval timeout{3, 0};  // bounded: a lost answer ends the client, not the bench
  ::setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof timeout);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  if (from) {
    ::inet_pton(AF_INET, from, &addr.sin_addr);
    ::bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr);
  }
  addr.sin_port = htons(port);
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (::connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) {
    ::close(fd);
    return -1;
  }
  return fd;
}

}  // namespace

std::int64_t now_us() {
  return std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

std::string slurp(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::uint16_t free_port() {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  ::bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr);
  socklen_t len = sizeof addr;
  ::getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &len);
  ::close(fd);
  return ntohs(addr.sin_port);
}

bool wait_for_port(std::uint16_t port, std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (std::chrono::steady_clock::now() < deadline) {
    if (const int fd = connect_to(port); fd >= 0) {
      ::close(fd);
      return true;
    }
    std::this_thread::sleep_for(20ms);
  }
  return false;
}

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<std::size_t>(p * static_cast<double>(v.size())))];
}

double median(std::vector<double> v) { return percentile(std::move(v), 0.5); }

// /proc/PID/task/*/schedstat counts ns; /proc/PID/stat counts 10 ms ticks, too coarse here.
double process_cpu_us(pid_t pid) {
  double ns = 0;
  std::error_code ec;
  for (const auto& task : fs::directory_iterator("/proc/" + std::to_string(pid) + "/task", ec)) {
    std::istringstream fields(slurp(task.path() / "schedstat"));
    double run = 0;
    if (fields >> run) ns += run;
  }
  return ns / 1000;
}

// Both frames on the wire, t3.5 after each, and the slave's answer delay.
LineLimit line_limit(unsigned baud) {
  const auto t = unima::modbus::rtu_timing(baud, false, 1);
  const double wire = static_cast<double>((query_bytes + answer_bytes) * 10) * 1e6 / baud;
  return {baud, wire + 2.0 * static_cast<double>(t.frame_gap.count()) + answer_delay_ms * 1000.0};
}

// --- a client --------------------------------------------------------------------------

ClientResult run_client(std::uint16_t port, std::uint8_t unit, const char* from, std::int64_t until_us,
                        std::size_t max_requests, const std::function<int(std::size_t)>& pause_us) {
  ClientResult result;
  const int fd = connect_to(port, from);
  if (fd < 0) {
    result.error = "cannot connect";
    return result;
  }
  for (std::uint16_t id = 1; result.requests.size() < max_requests && now_us() < until_us; ++id) {
    const std::uint8_t query[] = {static_cast<std::uint8_t>(id >> 8), static_cast<std::uint8_t>(id), 0, 0, 0, 6, unit,
                                  0x03, 0x00, 0x00, 0x00, 0x0A};
    const auto sent = now_us();
    if (::send(fd, query, sizeof query, MSG_NOSIGNAL) != static_cast<ssize_t>(sizeof query)) {
      result.error = "send failed";
      break;
    }
    std::uint8_t answer[7 + 22];
    std::size_t got = 0;
    while (got < 9) {  // the header and the function and byte count, or an exception's code
      const auto n = ::recv(fd, answer + got, sizeof answer - got, 0);
      if (n <= 0) break;
      got += static_cast<std::size_t>(n);
      if (got >= 9 && answer[7] == 0x03) {
        while (got < sizeof answer) {
          const auto m = ::recv(fd, answer + got, sizeof answer - got, 0);
          if (m <= 0) break;
          got += static_cast<std::size_t>(m);
        }
      }
    }
    const auto answered = now_us();
    if (got != sizeof answer || answer[0] != query[0] || answer[1] != query[1] || answer[6] != unit ||
        answer[7] != 0x03 || answer[8] != 20) {
      result.error = format("unit %u, request %u: a wrong answer (%zu bytes, function %02X, %02X)", unit, id, got,
                            got > 7 ? answer[7] : 0, got > 8 ? answer[8] : 0);
      break;
    }
    result.requests.push_back({sent, answered});
    if (const auto p = pause_us(result.requests.size()); p > 0) std::this_thread::sleep_for(std::chrono::microseconds(p));
  }
  ::close(fd);
  return result;
}

namespace {

std::size_t answered_within(const ClientResult& c, std::int64_t from, std::int64_t until) {
  return static_cast<std::size_t>(std::count_if(c.requests.begin(), c.requests.end(), [&](const Request& r) {
    return r.answered_us >= from && r.answered_us < until;
  }));
}

}  // namespace

// --- the simulated wire, the daemon, a line: the simulator and a gateway in front of it ---

SimulatedWire::SimulatedWire(unsigned baud, std::uint8_t unit, const Options& options, const std::string& label)
    : baud_(baud), unit_(unit) {
  if (!options.frames.empty()) {
    static int runs = 0;
    keep_as_ = fs::path(options.frames) / (std::to_string(++runs) + "-" + label + "-" + std::to_string(baud) + ".log");
  }
  char pattern[] = "/tmp/unima-gateway-bench-XXXXXX";
  if (!::mkdtemp(pattern)) throw std::runtime_error("mkdtemp failed");
  dir_ = pattern;
  const auto sim_out = dir_ / "sim.out";
  sim_ = std::make_unique<ChildProcess>(
      std::vector<std::string>{UNIMA_SLAVE_SIM, "--pty", pty().string(), "--baud", std::to_string(baud), "--frames",
                               frames_path().string(), "--slave",
                               std::to_string(unit) + "=wecon-lx5v,slow=" + std::to_string(answer_delay_ms)},
      unima::test_support::writing_to(sim_out));
  for (int i = 0; i < 250 && slurp(sim_out).find("ready") == std::string::npos; ++i) std::this_thread::sleep_for(20ms);
  if (slurp(sim_out).find("ready") == std::string::npos) throw std::runtime_error("the simulator did not start: " + slurp(sim_out));
}

SimulatedWire::~SimulatedWire() {
  sim_->stop(SIGTERM, 5s);
  std::error_code ec;
  if (!keep_as_.empty()) fs::copy_file(frames_path(), keep_as_, fs::copy_options::overwrite_existing, ec);
  fs::remove_all(dir_, ec);
}

std::vector<Frame> SimulatedWire::frames() const {
  std::vector<Frame> out;
  std::istringstream in(slurp(frames_path()));
  for (std::string line; std::getline(in, line);) {
    std::istringstream fields(line);
    Frame f{};
    std::string direction;
    if (fields >> f.us >> direction) out.push_back({f.us, direction == "rx"});
  }
  return out;
}

Daemon::Daemon(const fs::path& dir, const std::string& yaml) : dir_(dir), port_(free_port()) {
  auto text = yaml;
  for (auto at = text.find("@PORT@"); at != std::string::npos; at = text.find("@PORT@"))
    text.replace(at, 6, std::to_string(port_));
  std::ofstream(dir_ / "bridge.yaml") << text;
  process_ = std::make_unique<ChildProcess>(std::vector<std::string>{UNIMA_BRIDGED, "--config", (dir_ / "bridge.yaml").string()},
                                            unima::test_support::writing_to(dir_ / "bridged.log"));
  if (!wait_for_port(port_, 10s)) throw std::runtime_error("unima-bridged did not listen: " + log());
}

Daemon::~Daemon() { process_->stop(SIGTERM, 5s); }

std::string single_line_yaml(const SimulatedWire& wire) {
  return format("unimabus: { address: 5, transport: sim }\n"
                "modbus:\n"
                "  mode: master\n"
                "  address: 1\n"
                "  tcp: { listen: 127.0.0.1, port: @PORT@, max_clients: 64 }\n"
                "  rtu: { device: %s, baud: %u }\n"
                "  master: { response_timeout: 1s }\n"
                "  gateway: { units: [%u], timeout: 1s, wait: 5s, priority: [%s] }\n"
                "log: { level: warn }\n"
                "status: { socket: %s }\n",
                wire.pty().c_str(), wire.baud(), unsigned{wire.unit()}, priority_address,
                (wire.dir() / "control.sock").c_str());
}

namespace {

enum class Gateway { bridge, mbusd };

const char* name(Gateway g) { return g == Gateway::bridge ? "unima-bridged" : "mbusd"; }

class Line {
 public:
  Line(Gateway gateway, unsigned baud, const Options& options) : wire_(baud, unit, options, name(gateway)) {
    const auto pty = wire_.pty().string();
    if (gateway == Gateway::bridge) {
      bridge_ = std::make_unique<Daemon>(wire_.dir(), single_line_yaml(wire_));
      return;
    }
    // -R 2: its pause between requests, the least whole millisecond not under t3.5 at
    // 19200 baud; -N 1: one try, as the bridge; -L -: no log file. Both wait 1 s for an
    // answer: on a loaded machine the simulator may not run for a few hundred ms, and a
    // time-out then would be the host's, not the gateway's.
    mbusd_port_ = free_port();
    mbusd_ = std::make_unique<ChildProcess>(
        std::vector<std::string>{options.mbusd, "-d", "-L", "-", "-p", pty, "-s", std::to_string(baud), "-A", "127.0.0.1",
                                 "-P", std::to_string(mbusd_port_), "-N", "1", "-R", "2", "-W", "1000", "-T", "0"},
        unima::test_support::writing_to(wire_.dir() / "server.log"));
    if (!wait_for_port(mbusd_port_, 10s)) throw std::runtime_error("mbusd did not listen: " + slurp(wire_.dir() / "server.log"));
  }
  ~Line() {
    if (mbusd_) mbusd_->stop(SIGTERM, 5s);
  }
  Line(const Line&) = delete;
  Line& operator=(const Line&) = delete;

  std::uint16_t port() const { return bridge_ ? bridge_->port() : mbusd_port_; }
  /// The gateway's CPU time so far, in µs.
  double cpu_us() const { return bridge_ ? bridge_->cpu_us() : process_cpu_us(mbusd_->pid()); }
  const SimulatedWire& wire() const { return wire_; }

 private:
  SimulatedWire wire_;  // first made, last gone: the gateway goes before its line
  std::unique_ptr<Daemon> bridge_;
  std::unique_ptr<ChildProcess> mbusd_;
  std::uint16_t mbusd_port_ = 0;
};

}  // namespace

double BusyRun::rate() const {
  std::size_t all = 0;
  for (const auto c : counts) all += c;
  return static_cast<double>(all) / seconds;
}

double BusyRun::worst_fairness_percent() const {
  const double mean = rate() * seconds / static_cast<double>(counts.size());
  double worst = 0;
  for (const auto c : counts) worst = std::max(worst, std::abs(static_cast<double>(c) - mean) / mean * 100.0);
  return worst;
}

// The priority peer pauses a pseudo-random 0..2 transactions between its requests.
BusyRun busy(std::uint16_t port, const SimulatedWire& wire, double seconds, bool priority) {
  const auto start = now_us();
  const auto from = start + static_cast<std::int64_t>(busy_warmup_s * 1e6);
  const auto until = from + static_cast<std::int64_t>(seconds * 1e6);
  const auto most = static_cast<std::size_t>((busy_warmup_s + seconds) * line_limit(wire.baud()).per_second() * 2) + 100;
  std::vector<ClientResult> results(busy_clients + (priority ? 1 : 0));
  std::vector<std::thread> threads;
  for (std::size_t i = 0; i < busy_clients; ++i)
    threads.emplace_back([&, i] { results[i] = run_client(port, wire.unit(), nullptr, until, most, [](std::size_t) { return 0; }); });
  if (priority) {
    const auto transaction = static_cast<std::uint32_t>(line_limit(wire.baud()).transaction_us);
    threads.emplace_back([&, transaction] {
      std::uint32_t lcg = 2463534242u;
      results.back() = run_client(port, wire.unit(), priority_address, until, most, [&](std::size_t) {
        lcg = lcg * 1664525u + 1013904223u;
        return static_cast<int>((lcg >> 8) % (2 * transaction));
      });
    });
  }
  for (auto& t : threads) t.join();
  BusyRun run;
  run.seconds = seconds;
  for (std::size_t i = 0; i < busy_clients; ++i) run.counts.push_back(answered_within(results[i], from, until));
  if (priority)
    for (const auto& r : results.back().requests)
      if (r.answered_us >= from && r.answered_us < until) run.priority_latency_us.push_back(static_cast<double>(r.answered_us - r.sent_us));
  for (const auto& r : results)
    if (!r.error.empty()) run.error = r.error;
  const auto frames = wire.frames();
  if (priority)
    for (const auto& r : results.back().requests) {
      if (r.answered_us < from || r.answered_us >= until) continue;
      run.priority_line_turns.push_back(static_cast<double>(std::count_if(frames.begin(), frames.end(), [&](const Frame& f) {
        return f.rx && f.us >= r.sent_us && f.us <= r.answered_us;
      })));
    }
  for (std::size_t i = 1; i < frames.size(); ++i) {
    if (frames[i].us < from || frames[i].us >= until) continue;
    const auto span = static_cast<double>(frames[i].us - frames[i - 1].us);
    if (frames[i - 1].rx && !frames[i].rx) run.slave_us.push_back(span);
    if (!frames[i - 1].rx && frames[i].rx) run.gap_us.push_back(span);
  }
  return run;
}

namespace {

BusyRun busy(const Line& line, double seconds, bool priority) { return busy(line.port(), line.wire(), seconds, priority); }

// One client on an idle line: its latency minus the line time of its transaction, in µs.
std::vector<double> overhead(const Line& line, std::size_t requests) {
  const auto pause = static_cast<int>(line_limit(line.wire().baud()).transaction_us);  // the line idle before each
  const auto result = run_client(line.port(), unit, nullptr, now_us() + 30'000'000, requests, [&](std::size_t) { return pause; });
  if (!result.error.empty()) throw std::runtime_error("overhead client: " + result.error);
  const auto frames = line.wire().frames();
  std::vector<double> out;
  std::size_t f = 0;
  for (const auto& r : result.requests) {
    while (f < frames.size() && !(frames[f].rx && frames[f].us >= r.sent_us)) ++f;
    if (f + 1 >= frames.size() || frames[f + 1].rx || frames[f + 1].us > r.answered_us) continue;
    const auto line_time = frames[f + 1].us - frames[f].us;
    out.push_back(static_cast<double>(r.answered_us - r.sent_us - line_time));
  }
  return out;
}

}  // namespace

// 8 connections with 8 requests in flight each keep the daemon's loop busy, so what the
// gateway's work costs the loop shows (at depth 1 a run measures wake-ups, not the loop).
double bank_rate(const Options& options, std::uint16_t port, double seconds) {
  const std::string command = options.load + " --port " + std::to_string(port) +
                              " --connections 8 --depth 8 --function 4 --unit 1 --address 0x1020 --quantity 8"
                              " --duration " + std::to_string(seconds) + " --warmup 0.2 --json";
  std::FILE* pipe = ::popen(command.c_str(), "r");
  if (!pipe) throw std::runtime_error("cannot run " + options.load);
  std::string out;
  char buffer[512];
  while (std::fgets(buffer, sizeof buffer, pipe)) out += buffer;
  if (::pclose(pipe) != 0) throw std::runtime_error("unima-bench-load failed: " + out);
  const auto at = out.find("\"rps\":");
  if (at == std::string::npos) throw std::runtime_error("unima-bench-load said: " + out);
  return std::stod(out.substr(at + 6));
}

// The daemon, mbusd and the simulator wait for their timers the same way, so on a loaded
// machine a late answer or a long gap on the line is this, not the gateway.
struct HostLatency::State {
  std::atomic<bool> stop{false};
  std::vector<double> late_us;
  std::thread thread;
};

HostLatency::HostLatency() : state_(std::make_unique<State>()) {
  state_->thread = std::thread([state = state_.get()] {
    for (auto next = std::chrono::steady_clock::now() + 5ms; !state->stop; next += 5ms) {
      std::this_thread::sleep_until(next);
      state->late_us.push_back(static_cast<double>(
          std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::steady_clock::now() - next).count()));
      next = std::max(next, std::chrono::steady_clock::now());  // a late wake-up is counted once
    }
  });
}

HostLatency::~HostLatency() { stop(); }

std::vector<double> HostLatency::stop() {
  state_->stop = true;
  if (state_->thread.joinable()) state_->thread.join();
  return state_->late_us;
}

std::string host_latency_line(const std::vector<double>& late) {
  const auto over_1ms = std::count_if(late.begin(), late.end(), [](double us) { return us > 1000; });
  return format("Host wake-up latency during the bench (a thread on a 5 ms grid, %zu wake-ups): p50 %.2f ms, p99 "
                "%.2f ms, max %.2f ms, %.1f %% later than 1 ms; load average at the end: %s",
                late.size(), percentile(late, 0.5) / 1000, percentile(late, 0.99) / 1000, percentile(late, 1.0) / 1000,
                100.0 * static_cast<double>(over_1ms) / static_cast<double>(std::max<std::size_t>(late.size(), 1)),
                slurp("/proc/loadavg").c_str());
}

std::string format(const char* f, ...) {
  char text[1024];
  va_list args;
  va_start(args, f);
  std::vsnprintf(text, sizeof text, f, args);
  va_end(args);
  return text;
}

std::string each_round(const std::vector<double>& values, double scale) {
  std::string out;
  for (const auto v : values) out += format("%s%.3g", out.empty() ? "" : " ", v * scale);
  return out;
}

}  // namespace gateway_bench

using namespace gateway_bench;

int main(int argc, char** argv) {
  Options options;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const auto value = [&]() -> std::string { return i + 1 < argc ? argv[++i] : ""; };
    if (arg == "--quick") options.quick = true;
    else if (arg == "--lines") options.lines = true;
    else if (arg == "--rounds") options.rounds = std::atoi(value().c_str());
    else if (arg == "--seconds") options.seconds = std::atof(value().c_str());
    else if (arg == "--mbusd") options.mbusd = value();
    else if (arg == "--load") options.load = value();
    else if (arg == "--report") options.report = value();
    else if (arg == "--frames") options.frames = value();
    else {
      std::fprintf(stderr,
                   "usage: gateway_bench [--lines] [--quick] [--rounds 1..15] [--seconds 0.5..20] [--load unima-bench-load]\n"
                   "                     [--mbusd PATH] [--report FILE] [--frames DIR]\n");
      return 2;
    }
  }
  if (options.quick) {
    options.rounds = 1;
    options.seconds = 0.7;
  }
  options.rounds = std::clamp(options.rounds, 1, 15);  // bounded: at most a few minutes
  options.seconds = std::clamp(options.seconds, 0.5, 20.0);
  ::signal(SIGPIPE, SIG_IGN);
  if (options.lines) return run_lines(options);
  const std::size_t overhead_requests = options.quick ? 50 : 400;

  std::vector<Gateway> gateways{Gateway::bridge};
  if (!options.mbusd.empty()) gateways.push_back(Gateway::mbusd);
  const std::vector<unsigned> bauds{19200, 115200};
  std::map<std::pair<int, unsigned>, std::vector<double>> rates, fairness, slave_ms, gap_ms, gap_p90_ms,
      cpu_per_transaction;  // (gateway, baud)
  std::vector<double> priority_p99, priority_turns_max, overhead_p99, overhead_p90, overhead_p50, bank_ratio, bank_idle, bank_busy;
  std::string errors;
  const auto failed = [&](const std::string& what, const std::string& error) {
    if (!error.empty()) errors += what + ": " + error + "\n";
  };
  HostLatency host;
  try {
    for (int round = 0; round < options.rounds; ++round) {
      std::printf("gateway_bench: round %d of %d\n", round + 1, options.rounds);
      std::fflush(stdout);
      for (const auto baud : bauds)
        for (const auto g : gateways) {
          const Line line(g, baud, options);
          const auto cpu_before = line.cpu_us();
          const auto run = busy(line, options.seconds, false);
          // Per transaction answered in all, warm-up included: what it costs the gateway's loop.
          const auto answered = run.rate() * run.seconds;
          cpu_per_transaction[{static_cast<int>(g), baud}].push_back((line.cpu_us() - cpu_before) /
                                                                     std::max(answered, 1.0) * run.seconds /
                                                                     (run.seconds + 0.3));
          failed(format("%s at %u baud", name(g), baud), run.error);
          rates[{static_cast<int>(g), baud}].push_back(run.rate());
          fairness[{static_cast<int>(g), baud}].push_back(run.worst_fairness_percent());
          slave_ms[{static_cast<int>(g), baud}].push_back(median(run.slave_us) / 1000);
          gap_ms[{static_cast<int>(g), baud}].push_back(median(run.gap_us) / 1000);
          gap_p90_ms[{static_cast<int>(g), baud}].push_back(percentile(run.gap_us, 0.9) / 1000);
        }
      {
        const Line line(Gateway::bridge, 19200, options);
        const auto run = busy(line, options.seconds, true);
        failed("priority", run.error);
        priority_p99.push_back(percentile(run.priority_latency_us, 0.99));
        priority_turns_max.push_back(percentile(run.priority_line_turns, 1.0));
      }
      {
        const Line line(Gateway::bridge, 115200, options);
        const auto o = overhead(line, overhead_requests);
        overhead_p99.push_back(percentile(o, 0.99));
        overhead_p50.push_back(percentile(o, 0.5));
        overhead_p90.push_back(percentile(o, 0.9));
        if (!options.load.empty()) {
          // Idle and busy in turn within the round, the order swapped every other round.
          const auto idle_rate = [&] { return bank_rate(options, line.port(), options.seconds); };
          const auto busy_rate = [&] {
            double rate = 0;
            std::thread load([&] { rate = bank_rate(options, line.port(), options.seconds); });
            const auto run = busy(line, options.seconds, false);
            load.join();
            failed("banks beside the gateway", run.error);
            return rate;
          };
          double idle = 0, busy_ = 0;
          if (round % 2 == 0) {
            idle = idle_rate();
            busy_ = busy_rate();
          } else {
            busy_ = busy_rate();
            idle = idle_rate();
          }
          bank_idle.push_back(idle);
          bank_busy.push_back(busy_);
          bank_ratio.push_back(busy_ / idle);
        }
      }
    }
  } catch (const std::exception& e) {
    host.stop();
    std::fprintf(stderr, "gateway_bench: %s\n", e.what());
    return 2;
  }
  const auto late = host.stop();

  std::string report = format("Gateway bench: %d round(s) of %.1f s per run, %zu clients, a read of 10 registers "
                              "(%zu + %zu bytes), slave answer delay %d ms; medians of the rounds.\n\n",
                              options.rounds, options.seconds, busy_clients, query_bytes, answer_bytes, answer_delay_ms);
  report += "| gateway | baud | line limit | forwarded/s | of the limit (≥ 90 %) | worst client off the mean (≤ 10 %) "
            "| request → answer end: played, measured | answer end → next request: t3.5, median, p90 |\n"
            "|---|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const auto baud : bauds)
    for (const auto g : gateways) {
      const auto limit = line_limit(baud);
      const auto rate = median(rates[{static_cast<int>(g), baud}]);
      const auto worst = median(fairness[{static_cast<int>(g), baud}]);
      const auto key = std::pair{static_cast<int>(g), baud};
      const auto t3_5 = static_cast<double>(unima::modbus::rtu_timing(baud, false, 1).frame_gap.count()) / 1000;
      report += format("| %s | %u | %.1f/s (%.2f ms) | %.1f | %.1f %% %s | %.1f %% %s | %.2f, %.2f ms | %.2f, %.2f, %.2f ms |\n",
                       name(g), baud, limit.per_second(), limit.transaction_us / 1000, rate,
                       100 * rate / limit.per_second(), verdict(rate >= 0.9 * limit.per_second()), worst,
                       verdict(worst <= 10), limit.transaction_us / 1000 - t3_5, median(slave_ms[key]), t3_5,
                       median(gap_ms[key]), median(gap_p90_ms[key]));
    }
  report += "\nCPU time of the gateway process per forwarded transaction (its threads' run time, schedstat):";
  for (const auto baud : bauds)
    for (const auto g : gateways)
      report += format(" %s at %u: %.0f µs;", name(g), baud, median(cpu_per_transaction[{static_cast<int>(g), baud}]));
  report += "\n";
  const auto bound = 2 * line_limit(19200).transaction_us;
  report += format("\nPriority peer among 8 busy clients, 19200 baud: p99 %.2f ms, bound (one transaction in progress "
                   "+ its own) %.2f ms: %s; p99 per round, ms: %s; requests on the line while one of its waited, its "
                   "own included, at most (per round): %s\n",
                   median(priority_p99) / 1000, bound / 1000, verdict(median(priority_p99) <= bound),
                   each_round(priority_p99, 1e-3).c_str(), each_round(priority_turns_max, 1).c_str());
  report += format("Overhead, one client on an idle line at 115200 baud (latency minus line time): p50 %.3f ms, p90 "
                   "%.3f ms, p99 %.3f ms (≤ 1 ms): %s; p99 per round, ms: %s\n",
                   median(overhead_p50) / 1000, median(overhead_p90) / 1000, median(overhead_p99) / 1000,
                   verdict(median(overhead_p99) <= 1000), each_round(overhead_p99, 1e-3).c_str());
  if (!bank_ratio.empty()) {
    const auto rounds = each_round(bank_ratio, 1);
    report += format("Own banks (function 4, 8 connections × depth 8): %.0f/s with the gateway idle, %.0f/s with it "
                     "busy: %.1f %% (within 3 %%): %s; busy ÷ idle per round: %s\n",
                     median(bank_idle), median(bank_busy), 100 * median(bank_ratio),
                     verdict(std::abs(median(bank_ratio) - 1) <= 0.03), rounds.c_str());
  }
  if (options.mbusd.empty()) report += "mbusd: not run (no --mbusd PATH)\n";
  report += "\n" + host_latency_line(late);
  if (!errors.empty()) report += "\nERRORS:\n" + errors;
  std::fputs(report.c_str(), stdout);
  if (!options.report.empty()) std::ofstream(options.report) << report;
  return errors.empty() ? 0 : 1;
}
