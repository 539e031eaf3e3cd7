#pragma once
// What gateway_bench's two parts share: gateway_bench.cpp (one line, issue 31) defines
// these, lines_bench.cpp (several lines from one daemon, issue 39) uses them too.

#include <sys/types.h>

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "tests/support/child_process.hpp"

namespace gateway_bench {

using namespace std::chrono_literals;

constexpr std::size_t query_bytes = 8, answer_bytes = 5 + 2 * 10;  // a read of D0..D9
constexpr int answer_delay_ms = 1;                                  // the simulated slave's
constexpr std::size_t busy_clients = 8;

struct Options {
  bool quick = false;
  bool lines = false;  // the several-lines runs instead of the single-line ones
  int rounds = 5;
  double seconds = 4;
  std::string mbusd, load, report;
  std::string frames;  // a directory to keep every run's frame log in
};

std::int64_t now_us();
std::string slurp(const std::filesystem::path& path);
std::uint16_t free_port();
bool wait_for_port(std::uint16_t port, std::chrono::milliseconds timeout);
double percentile(std::vector<double> v, double p);
double median(std::vector<double> v);
/// A process's CPU time so far, in µs: its threads' run time from schedstat.
double process_cpu_us(pid_t pid);

/// The line's physical limit for one read of D0..D9.
struct LineLimit {
  unsigned baud;
  double transaction_us;
  double per_second() const { return 1e6 / transaction_us; }
};
LineLimit line_limit(unsigned baud);

struct Request {
  std::int64_t sent_us, answered_us;
};
struct ClientResult {
  std::vector<Request> requests;
  std::string error;  // empty while every answer was right
};
/// Asks `unit` for D0..D9 until `until_us` or `max_requests`, pausing `pause_us(i)` µs
/// after answer i; from the address `from` when it is not null.
ClientResult run_client(std::uint16_t port, std::uint8_t unit, const char* from, std::int64_t until_us,
                        std::size_t max_requests, const std::function<int(std::size_t)>& pause_us);

struct Frame {
  std::int64_t us;
  bool rx;
};

/// foreign-slave-sim on a pseudo-terminal in a temporary directory, playing an 8N1 wire at
/// `baud` with a WECON PLC at `unit`; every frame logged with its time.
class SimulatedWire {
 public:
  SimulatedWire(unsigned baud, std::uint8_t unit, const Options& options, const std::string& label);
  ~SimulatedWire();
  SimulatedWire(const SimulatedWire&) = delete;
  SimulatedWire& operator=(const SimulatedWire&) = delete;

  unsigned baud() const { return baud_; }
  std::uint8_t unit() const { return unit_; }
  const std::filesystem::path& dir() const { return dir_; }
  std::filesystem::path pty() const { return dir_ / "ttySIM"; }
  std::vector<Frame> frames() const;

 private:
  std::filesystem::path frames_path() const { return dir_ / "frames.log"; }
  std::filesystem::path dir_, keep_as_;
  unsigned baud_;
  std::uint8_t unit_;
  std::unique_ptr<unima::test_support::ChildProcess> sim_;
};

/// unima-bridged with `yaml` as its config (`@PORT@` replaced by its free TCP port), in
/// `dir`; stopped with SIGTERM when the object goes.
class Daemon {
 public:
  Daemon(const std::filesystem::path& dir, const std::string& yaml);
  ~Daemon();
  Daemon(const Daemon&) = delete;
  Daemon& operator=(const Daemon&) = delete;

  std::uint16_t port() const { return port_; }
  double cpu_us() const { return process_cpu_us(process_->pid()); }
  std::string log() const { return slurp(dir_ / "bridged.log"); }

 private:
  std::filesystem::path dir_;
  std::uint16_t port_ = 0;
  std::unique_ptr<unima::test_support::ChildProcess> process_;
};

/// The single-line daemon of the gateway runs: master mode, `modbus.rtu` on the wire, its
/// gateway routing the wire's unit.
std::string single_line_yaml(const SimulatedWire& wire);

/// 8 clients asking one unit without pause for `seconds` after a short warm-up; with
/// `priority`, a priority peer beside them.
struct BusyRun {
  double seconds = 0;
  std::vector<std::size_t> counts;  // answered within the window, per busy client
  std::vector<double> priority_latency_us;
  // For each of the priority peer's requests, the requests that went on the line between its
  // sending and its answer, its own included.
  std::vector<double> priority_line_turns;
  std::vector<double> slave_us, gap_us;  // from the frame log: request to answer, answer to next request
  std::string error;
  double rate() const;
  double worst_fairness_percent() const;  // the largest distance from the mean, in % of it
  double answered() const { return rate() * seconds; }
};
constexpr double busy_warmup_s = 0.3;
BusyRun busy(std::uint16_t port, const SimulatedWire& wire, double seconds, bool priority);

/// unima-bench-load on the daemon's own bank C (function 4, unit 1, 8 connections × depth
/// 8): requests per second.
double bank_rate(const Options& options, std::uint16_t port, double seconds);

/// How late this host wakes a thread sleeping on a 5 ms grid, sampled until stop().
class HostLatency {
 public:
  HostLatency();
  ~HostLatency();
  std::vector<double> stop();

 private:
  struct State;
  std::unique_ptr<State> state_;
};
std::string host_latency_line(const std::vector<double>& late_us);

std::string format(const char* f, ...) __attribute__((format(printf, 1, 2)));
std::string each_round(const std::vector<double>& values, double scale);
inline const char* verdict(bool met) { return met ? "met" : "MISSED"; }

/// The several-lines runs (lines_bench.cpp): gateway_bench's exit code.
int run_lines(const Options& options);

}  // namespace gateway_bench
