// master_bench: does the master hold its periods when one of three slaves is dead?
//
// The daemon (master mode, RTU at 38400 baud on a pseudo-terminal) polls a SIC184 v3.21,
// a SIC184 v2.08 that never answers, and the stepper driver, with the periods below, for
// up to a minute. The simulator logs every frame with its arrival time; for each request
// of the live slaves the intervals between its frames are compared with its period.
//
// Pass: every single interval of every live request within ±5 % of its period, except
// each request's first interval (from its first frame to its second), and at least 95 %
// of the frames it should have had (no starvation). The first interval is start-up: each
// device's first request goes before anyone knows whether it answers, and the dead slave's
// first time-out (100 ms, longer than the line's gaps) moves the live schedule once; the
// table shows it apart. The dead slave's frames are listed with their times: its probes
// must keep coming (no starved recovery). Exit 0 on pass, 1 on fail, 2 when it could not
// run.

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "tests/support/child_process.hpp"

namespace {


using namespace std::chrono_literals;
namespace fs = std::filesystem;

struct Expected {
  std::string request;  // the RTU frame as the simulator logs it
  std::string what;
  double period_ms;
};

// The plan of the config below (`unima-bridge check` prints it): frames of live slaves.
const std::vector<Expected> expected{
    {"01 03 04 24 00 02 85 30", "SIC184 v3 POS_ACT_REAL", 100},
    {"01 02 13 88 00 08 FD 62", "SIC184 v3 IN1..IN8", 200},
    {"01 03 03 EA 00 01 A5 BA", "SIC184 v3 STATUS", 250},
    {"01 05 17 70 00 00 C9 A5", "SIC184 v3 OUT1 <- X.0", 1000},
    {"03 03 00 00 00 02 C5 E9", "stepper STEP_ANGLE+SUBDIVISION", 200},
    {"03 03 00 16 00 02 24 2D", "stepper POSITION", 500},
    {"03 06 00 08 00 00 09 EA", "stepper TEST_SPEED <- X+0x00", 1000},
};

const char* config_template = R"(unimabus: { address: 5, transport: sim }
modbus:
  mode: master
  rtu: { device: @PTY@, baud: 38400 }
  master:
    response_timeout: 100ms
    retries: 1
    degrade_after: 3
    backoff: 1s
    backoff_max: 10s
    devices: { 1: { profile: sic184-v3 }, 2: { profile: sic184-v2 }, 3: { profile: stepper-driver } }
blocks:
  - { type: poll, device: 1, point: POS_ACT_REAL, period: 100ms, output: 1 }
  - { type: poll, device: 1, point: IN, period: 200ms, output: 2 }
  - { type: poll, device: 1, point: STATUS, period: 250ms, output: 3 }
  - { type: send, device: 1, point: OUT1, period: 1s, source: X.0 }
  - { type: poll, device: 2, point: XACT, period: 100ms, output: 4 }
  - { type: poll, device: 2, point: MOTOR_STATUS, period: 500ms, output: 5 }
  - { type: poll, device: 3, point: STEP_ANGLE, period: 200ms, output: 6 }
  - { type: poll, device: 3, point: SUBDIVISION, period: 200ms, output: 7 }
  - { type: poll, device: 3, point: POSITION, period: 500ms, output: 8 }
  - { type: send, device: 3, point: TEST_SPEED, period: 1s, source: X+0x00 }
log: { level: info }
)";

std::string slurp(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

bool wait_for(const fs::path& file, const std::string& text, std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (std::chrono::steady_clock::now() < deadline) {
    if (slurp(file).find(text) != std::string::npos) return true;
    std::this_thread::sleep_for(20ms);
  }
  return false;
}

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<std::size_t>(p * static_cast<double>(v.size())))];
}

// While the daemon runs, how late this host wakes a sleeping thread up (a 10 ms grid):
// the daemon and the simulator wait for their timers the same way, so a late frame on an
// idle line is this, not the schedule.
struct HostLatency {
  std::vector<double> late_ms;
  std::size_t over(double ms) const {
    return static_cast<std::size_t>(std::count_if(late_ms.begin(), late_ms.end(), [&](double x) { return x > ms; }));
  }
};

HostLatency host_latency(std::chrono::seconds run) {
  HostLatency h;
  const auto start = std::chrono::steady_clock::now();
  for (auto next = start + 10ms; next < start + run; next += 10ms) {
    std::this_thread::sleep_until(next);
    h.late_ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - next).count());
  }
  return h;
}

struct Frame {
  std::int64_t us;
  std::string hex;
};

// An interval off by more than 5 %: when, and what was on the line between the moment the
// frame should have come and the moment it came (nothing: the host was late, not the
// schedule).
std::string describe_outlier(const Expected& e, const std::vector<std::int64_t>& t, std::size_t i,
                             const std::vector<Frame>& line_frames, std::int64_t first_frame) {
  const auto expected_at = t[i - 1] + static_cast<std::int64_t>(e.period_ms * 1000.0);
  std::string before;
  for (const auto& f : line_frames)
    if (f.us >= std::min(expected_at, t[i]) - 1000 && f.us < std::max(expected_at, t[i]) && f.hex != e.request)
      before += " [" + f.hex + "]";
  char text[512];
  std::snprintf(text, sizeof text, "    %s: frame %zu at %.4f s, interval %+.2f ms off; on the line meanwhile:%s\n",
                e.what.c_str(), i, static_cast<double>(t[i] - first_frame) / 1e6,
                static_cast<double>(t[i] - t[i - 1]) / 1000.0 - e.period_ms, before.empty() ? " nothing" : before.c_str());
  return text;
}

}  // namespace

int main(int argc, char** argv) {
  int seconds = 60;
  std::string report_path, frames_copy;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--seconds" && i + 1 < argc) seconds = std::atoi(argv[++i]);
    else if (arg == "--report" && i + 1 < argc) report_path = argv[++i];
    else if (arg == "--frames" && i + 1 < argc) frames_copy = argv[++i];
    else {
      std::fprintf(stderr, "usage: master_bench [--seconds 1..60] [--report FILE] [--frames FILE]\n");
      return 2;
    }
  }
  seconds = std::clamp(seconds, 1, 60);  // bounded: a minute at most

  char pattern[] = "/tmp/unima-master-bench-XXXXXX";
  if (!::mkdtemp(pattern)) return 2;
  const fs::path dir = pattern;
  const auto pty = dir / "ttySIM", frames = dir / "frames.log", sim_out = dir / "sim.out", log = dir / "daemon.log";
  using unima::test_support::ChildProcess;
  ChildProcess sim({UNIMA_SLAVE_SIM, "--pty", pty.string(), "--frames", frames.string(), "--slave", "1=sic184-v3",
                    "--slave", "2=sic184-v2,dead", "--slave", "3=stepper-driver"},
                   unima::test_support::writing_to(sim_out));
  if (!wait_for(sim_out, "ready", 5s)) {
    std::fprintf(stderr, "master_bench: the simulator did not start:\n%s", slurp(sim_out).c_str());
    return 2;
  }
  std::string config = config_template;
  config.replace(config.find("@PTY@"), 5, pty.string());
  config += "status: { socket: " + (dir / "control.sock").string() + " }\n";  // never the system's /run
  std::ofstream(dir / "bridge.yaml") << config;
  ChildProcess daemon({UNIMA_BRIDGED, "--config", (dir / "bridge.yaml").string()}, unima::test_support::writing_to(log));
  if (!wait_for(log, "running", 5s)) {
    std::fprintf(stderr, "master_bench: the daemon did not start:\n%s", slurp(log).c_str());
    return 2;
  }
  std::printf("master_bench: %d s, 3 slaves on %s at 38400 baud, slave 2 dead\n", seconds, pty.c_str());
  std::fflush(stdout);
  const auto host = host_latency(std::chrono::seconds(seconds));
  daemon.stop(SIGTERM, 5s);
  sim.stop(SIGTERM, 5s);

  // Frames by request, arrival times in µs.
  std::map<std::string, std::vector<std::int64_t>> arrivals;
  std::vector<std::int64_t> dead_frames;
  std::vector<Frame> line_frames;  // every request heard, in order
  std::int64_t first_frame = -1;
  std::istringstream in(slurp(frames));
  for (std::string line; std::getline(in, line);) {
    std::istringstream fields(line);
    std::int64_t us = 0;
    std::string direction, port;
    fields >> us >> direction >> port;
    std::string hex;
    std::getline(fields, hex);
    if (direction != "rx" || hex.size() < 2) continue;
    hex.erase(0, 1);
    if (first_frame < 0) first_frame = us;
    if (hex.starts_with("02 ")) dead_frames.push_back(us);
    arrivals[hex].push_back(us);
    line_frames.push_back({us, hex});
  }

  std::string report;
  char line[512];
  std::snprintf(line, sizeof line,
                "| request | period | frames (due) | first interval | mean interval | mean error | within ±5 %% | p99 |dev| | max |dev| |\n"
                "|---|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  report += line;
  bool pass = true;
  std::string outliers;
  for (const auto& e : expected) {
    const auto& t = arrivals[e.request];
    if (t.size() < 3) {
      std::snprintf(line, sizeof line, "| %s | %.0f ms | %zu | - | - | - | - | - | - |\n", e.what.c_str(), e.period_ms,
                    t.size());
      report += line;
      pass = false;
      continue;
    }
    // Every interval but the first (start-up, shown apart).
    std::vector<double> deviations;
    std::size_t within = 0;
    for (std::size_t i = 2; i < t.size(); ++i) {
      const double interval = static_cast<double>(t[i] - t[i - 1]) / 1000.0;
      deviations.push_back(std::abs(interval - e.period_ms));
      within += deviations.back() <= 0.05 * e.period_ms;
      if (deviations.back() > 0.05 * e.period_ms) outliers += describe_outlier(e, t, i, line_frames, first_frame);
    }
    const double first = static_cast<double>(t[1] - t[0]) / 1000.0;
    // The mean from the second frame to the last, so one late frame does not count twice.
    const double mean = static_cast<double>(t.back() - t[1]) / 1000.0 / static_cast<double>(deviations.size());
    const double mean_error = 100.0 * (mean - e.period_ms) / e.period_ms;
    const double share = 100.0 * static_cast<double>(within) / static_cast<double>(deviations.size());
    const double due = seconds * 1000.0 / e.period_ms;
    pass = pass && within == deviations.size() && static_cast<double>(t.size()) >= 0.95 * due;
    std::snprintf(line, sizeof line,
                  "| %s | %.0f ms | %zu (%.0f) | %.1f ms | %.3f ms | %+.3f %% | %.1f %% | %.1f ms | %.1f ms |\n",
                  e.what.c_str(), e.period_ms, t.size(), due, first, mean, mean_error, share,
                  percentile(deviations, 0.99), percentile(deviations, 1.0));
    report += line;
  }
  if (!outliers.empty()) report += "\nIntervals off by more than 5 %:\n" + outliers;
  std::snprintf(line, sizeof line,
                "\nHost wake-up latency during the run (a thread on a 10 ms grid, %zu wake-ups): p99 %.2f ms, max "
                "%.2f ms, %zu later than 2 ms, %zu later than 5 ms.\n",
                host.late_ms.size(), percentile(host.late_ms, 0.99), percentile(host.late_ms, 1.0), host.over(2.0),
                host.over(5.0));
  report += line;
  std::string times;
  for (const auto us : dead_frames) {
    std::snprintf(line, sizeof line, "%s%.2f", times.empty() ? "" : ", ", static_cast<double>(us - first_frame) / 1e6);
    times += line;
  }
  std::snprintf(line, sizeof line, "\nDead SIC184 v2.08 (address 2): %zu frames in %d s (tries, retries and probes), at s: ",
                dead_frames.size(), seconds);
  report += line + times + "\n";
  // Recovery is not starved: after its first frames the dead slave keeps being probed, at
  // most backoff_max (10 s) plus the patience of one probe interval apart.
  for (std::size_t i = 1; i < dead_frames.size(); ++i)
    if (dead_frames[i] - dead_frames[i - 1] > 20'000'000) pass = false;
  if (dead_frames.empty() || static_cast<double>(first_frame + static_cast<std::int64_t>(seconds) * 1'000'000 -
                                                 dead_frames.back()) > 20e6)
    pass = false;
  const auto daemon_log = slurp(log);
  std::istringstream l(daemon_log);
  for (std::string text; std::getline(l, text);)
    if (text.find("modbus master: device") != std::string::npos) report += "    " + text + "\n";
  report += pass ? "PASS: every interval of every live request after its first within ±5 % of its period, all "
                   "frames there, the dead slave probed\n"
                 : "FAIL: a live request's interval (after its first) off by more than 5 %, frames lost, or the dead "
                   "slave not probed\n";
  std::fputs(report.c_str(), stdout);
  if (!report_path.empty()) std::ofstream(report_path) << report;
  std::error_code ec;
  if (!frames_copy.empty()) fs::copy_file(frames, frames_copy, fs::copy_options::overwrite_existing, ec);
  fs::remove_all(dir, ec);
  return pass ? 0 : 1;
}
