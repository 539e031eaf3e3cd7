// gateway_bench --lines: several RS-485 lines from one daemon (`modbus.lines`, issue 39).
//
// The same pieces as the single-line runs (gateway_bench.cpp): foreign-slave-sim playing an
// 8N1 wire at the line's baud on a pseudo-terminal, 8 gateway clients asking D0..D9 without
// pause, the frame log, paired rounds. Measured, each round running every configuration
// once, one after the other:
//
//   two lines    one daemon, two master lines (unit 5 on line-a, unit 6 on line-b, each on
//                its own simulator), 8 clients per line at once, at 19200 and 115200 baud:
//                each line's forwarded transactions per second against its limit; beside
//                it, in the same round, the single-line daemon of gateway_bench
//   cpu          the daemon's CPU time per forwarded transaction in both of those runs
//   slave line   one daemon, a slave line (scada, 19200 baud, on a socat pty pair: a
//                libmodbus RTU master on the other end reads function 4 from the bridge's
//                address without pause) beside a master line (field, 115200 baud): the
//                SCADA's latency p99 while field only polls its slave every 100 ms (idle),
//                is saturated by 8 gateway clients besides, and is unplugged (its simulator
//                gone, the pty with it: each poll a failed write, logged; the count of
//                those warnings is printed, to show the line did fail). A master line
//                whose device is missing at start stops the daemon, so it goes after start.
//   tcp slave    unima-bench-load on bank C (function 4) of that daemon with both lines
//                idle against a daemon without `modbus.lines` (only modbus.tcp)
//
// Exit codes as the single-line runs': 0 when every run worked and every answer was
// right, 1 otherwise, 2 when it could not start; no time is asserted.

#include <modbus/modbus.h>

#include <algorithm>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cmath>
#include <cstdio>
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

#include "bench/gateway/gateway_bench.hpp"

namespace gateway_bench {
namespace {

namespace fs = std::filesystem;
using unima::test_support::ChildProcess;

constexpr std::uint8_t unit_a = 5, unit_b = 6;  // one foreign slave per master line
constexpr unsigned scada_baud = 19200;
constexpr unsigned field_baud = 115200;  // the master line beside the slave line: the most transactions a second
constexpr int bridge_address = 1;        // modbus.address: what the SCADA asks on the slave line
constexpr int bank_c = 0x1020, bank_c_registers = 8;

std::string common_yaml(const fs::path& dir) {
  return format("unimabus: { address: 5, transport: sim }\n"
                "log: { level: warn }\n"
                "status: { socket: %s }\n",
                (dir / "control.sock").c_str());
}

std::string gateway_line(const char* name, const std::string& device, unsigned baud, std::uint8_t unit) {
  return format("    %s: { device: %s, baud: %u, role: master, gateway: { units: [%u], timeout: 1s, wait: 5s } }\n", name,
                device.c_str(), baud, unsigned{unit});
}

std::string tcp_yaml() {
  return format("modbus:\n"
                "  address: %d\n"
                "  tcp: { listen: 127.0.0.1, port: @PORT@, max_clients: 64 }\n",
                bridge_address);
}

// --- two master lines saturated at once ---------------------------------------------------

struct SaturatedRun {
  std::vector<BusyRun> lines;
  double cpu_per_transaction_us = 0;
};

// The daemon's CPU time over the run per transaction answered in all, warm-up included (as
// gateway_bench counts it): what the lines' work costs the daemon.
double cpu_per_transaction(double cpu_us, const std::vector<BusyRun>& runs) {
  double answered = 0;
  for (const auto& r : runs) answered += r.answered();
  const double seconds = runs.front().seconds;
  return cpu_us / std::max(answered, 1.0) * seconds / (seconds + busy_warmup_s);
}

SaturatedRun saturate(const Daemon& daemon, const std::vector<const SimulatedWire*>& wires, double seconds) {
  SaturatedRun out;
  out.lines.resize(wires.size());
  const auto cpu_before = daemon.cpu_us();
  std::vector<std::thread> threads;
  for (std::size_t i = 0; i < wires.size(); ++i)
    threads.emplace_back([&, i] { out.lines[i] = busy(daemon.port(), *wires[i], seconds, false); });
  for (auto& t : threads) t.join();
  out.cpu_per_transaction_us = cpu_per_transaction(daemon.cpu_us() - cpu_before, out.lines);
  return out;
}

SaturatedRun one_line(unsigned baud, const Options& options) {
  const SimulatedWire wire(baud, unit_a, options, "one-line");
  const Daemon daemon(wire.dir(), single_line_yaml(wire));
  return saturate(daemon, {&wire}, options.seconds);
}

SaturatedRun two_lines(unsigned baud, const Options& options) {
  const SimulatedWire a(baud, unit_a, options, "line-a"), b(baud, unit_b, options, "line-b");
  const Daemon daemon(a.dir(), common_yaml(a.dir()) + tcp_yaml() + "  master: { response_timeout: 1s }\n  lines:\n" +
                                   gateway_line("line-a", a.pty().string(), baud, unit_a) +
                                   gateway_line("line-b", b.pty().string(), baud, unit_b));
  return saturate(daemon, {&a, &b}, options.seconds);
}

// --- the slave line beside a master line ------------------------------------------------

/// socat joining two pseudo-terminals at `a` and `b`, as the integration tests' SocatLink.
class SocatPair {
 public:
  SocatPair(const fs::path& a, const fs::path& b) {
    unima::test_support::SpawnOptions spawn;
    spawn.search_path = true;
    spawn.stop_signal = SIGTERM;
    socat_ = std::make_unique<ChildProcess>(
        std::vector<std::string>{"socat", "pty,rawer,link=" + a.string(), "pty,rawer,link=" + b.string()}, spawn);
    for (int i = 0; i < 250 && !(fs::exists(a) && fs::exists(b)); ++i) std::this_thread::sleep_for(20ms);
    if (!(fs::exists(a) && fs::exists(b))) throw std::runtime_error("socat did not make its pseudo-terminals");
  }

 private:
  std::unique_ptr<ChildProcess> socat_;
};

/// A libmodbus RTU master on the SCADA's end of the slave line, 19200 8N1.
class Scada {
 public:
  explicit Scada(const fs::path& device) : modbus_(modbus_new_rtu(device.c_str(), scada_baud, 'N', 8, 1)) {
    if (!modbus_) throw std::runtime_error("modbus_new_rtu failed");
    modbus_set_slave(modbus_, bridge_address);
    modbus_set_response_timeout(modbus_, 1, 0);  // bounded: a lost answer costs 1 s, not the bench
    if (modbus_connect(modbus_) != 0) throw std::runtime_error(std::string("the SCADA cannot open its end: ") + modbus_strerror(errno));
  }
  ~Scada() {
    modbus_close(modbus_);
    modbus_free(modbus_);
  }
  Scada(const Scada&) = delete;
  Scada& operator=(const Scada&) = delete;

  /// One read of bank C; an error's text, or empty when the answer was right.
  std::string read() {
    std::uint16_t registers[bank_c_registers];
    const int n = modbus_read_input_registers(modbus_, bank_c, bank_c_registers, registers);
    if (n == bank_c_registers) return {};
    return n < 0 ? std::string(modbus_strerror(errno)) : format("%d registers for %d", n, bank_c_registers);
  }

 private:
  modbus_t* modbus_;
};

enum class Field { idle, saturated, unplugged };
const char* name(Field f) { return f == Field::idle ? "idle" : f == Field::saturated ? "saturated" : "unplugged"; }

// The master polls its foreign slave, as on a site: a line whose device has gone then keeps
// failing, warning and trying again, which is the load an unplugged line puts on the daemon.
std::string field_poll_yaml() {
  return format("blocks:\n  - { type: poll, line: field, device: %u, profile: wecon-lx5v, operand: D0, period: 100ms, "
                "output: 1 }\n",
                unsigned{unit_a});
}

/// A directory under /tmp, removed with what is in it when the object goes.
class TempDir {
 public:
  TempDir() {
    char pattern[] = "/tmp/unima-lines-bench-XXXXXX";
    if (!::mkdtemp(pattern)) throw std::runtime_error("mkdtemp failed");
    path_ = pattern;
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

/// A daemon with the slave line `scada` and the master line `field`: the two-port site.
class Site {
 public:
  explicit Site(const Options& options)
      : field_(std::in_place, field_baud, unit_a, options, "field"),
        socat_(scada_end(), bridge_end()),
        daemon_(dir_.path(), common_yaml(dir_.path()) + tcp_yaml() + "  master: { response_timeout: 1s }\n  lines:\n" +
                                 format("    scada: { device: %s, baud: %u, role: slave }\n", bridge_end().c_str(), scada_baud) +
                                 gateway_line("field", field_->pty().string(), field_baud, unit_a) + field_poll_yaml()) {}

  const Daemon& daemon() const { return daemon_; }
  const SimulatedWire& field() const { return *field_; }
  fs::path scada_end() const { return dir_.path() / "scada"; }
  /// The field line's device goes, as a USB adapter pulled: the simulator ends, and its
  /// pseudo-terminal and the link to it with it.
  void unplug_field() { field_.reset(); }

 private:
  fs::path bridge_end() const { return dir_.path() / "bridge-end"; }
  TempDir dir_;  // first made, last gone
  std::optional<SimulatedWire> field_;
  SocatPair socat_;
  Daemon daemon_;
};

struct ScadaRun {
  std::vector<double> latency_us;  // each request's, within the window
  std::string error;
};

// The SCADA asks without pause for `seconds` after the warm-up; with `field_busy`, 8 gateway
// clients saturate the field line over the same window.
ScadaRun poll_scada(Site& site, double seconds, bool field_busy) {
  ScadaRun out;
  Scada scada(site.scada_end());
  // The slave line may open a moment after the TCP port listens: wait for a first answer.
  std::string first;
  for (int i = 0; i < 50 && !(first = scada.read()).empty(); ++i) std::this_thread::sleep_for(50ms);
  if (!first.empty()) {
    out.error = "no first answer on the slave line: " + first;
    return out;
  }
  std::optional<BusyRun> field;
  std::thread clients;
  if (field_busy) clients = std::thread([&] { field = busy(site.daemon().port(), site.field(), seconds, false); });
  const auto from = now_us() + static_cast<std::int64_t>(busy_warmup_s * 1e6);
  const auto until = from + static_cast<std::int64_t>(seconds * 1e6);
  constexpr std::size_t most = 200'000;
  for (std::size_t i = 0; i < most && now_us() < until; ++i) {
    const auto sent = now_us();
    if (auto error = scada.read(); !error.empty()) {
      out.error = format("SCADA request %zu: %s", i + 1, error.c_str());
      break;
    }
    if (sent >= from) out.latency_us.push_back(static_cast<double>(now_us() - sent));
  }
  if (clients.joinable()) clients.join();
  if (field && !field->error.empty()) out.error += (out.error.empty() ? "" : "; ") + ("field clients: " + field->error);
  return out;
}

// --- the report ---------------------------------------------------------------------------

std::string number(double v) { return std::abs(v) >= 1000 ? format("%.0f", v) : format("%.3g", v); }

// The median of the rounds and, in brackets, their range.
std::string range(const std::vector<double>& rounds, double scale, const char* unit_text) {
  if (rounds.empty()) return "-";
  const auto [lo, hi] = std::minmax_element(rounds.begin(), rounds.end());
  return number(median(rounds) * scale) + unit_text + " (rounds " + number(*lo * scale) + " – " + number(*hi * scale) + ")";
}

}  // namespace

int run_lines(const Options& options) {
  const std::vector<unsigned> bauds{19200, 115200};
  std::map<unsigned, std::vector<double>> one_rate, a_rate, b_rate, one_cpu, two_cpu;
  std::map<Field, std::vector<double>> scada_p99, scada_p50, daemon_cpu;  // daemon_cpu: % of one core
  std::vector<double> unplugged_failures;  // the field line's failed writes the daemon logged, per round
  std::vector<double> saturated_ratio, unplugged_ratio, tcp_lines, tcp_plain, tcp_ratio;
  std::string errors;
  const auto failed = [&](const std::string& what, const std::string& error) {
    if (!error.empty()) errors += what + ": " + error + "\n";
  };
  const std::string load_before = slurp("/proc/loadavg");
  HostLatency host;
  try {
    for (int round = 0; round < options.rounds; ++round) {
      std::printf("gateway_bench --lines: round %d of %d\n", round + 1, options.rounds);
      std::fflush(stdout);
      for (const auto baud : bauds) {
        // One line and two lines in turn, the order swapped every other round.
        std::optional<SaturatedRun> one, two;
        for (int i = 0; i < 2; ++i) {
          if ((i == 0) == (round % 2 == 0)) one = one_line(baud, options);
          else two = two_lines(baud, options);
        }
        failed(format("one line at %u baud", baud), one->lines[0].error);
        failed(format("line-a at %u baud", baud), two->lines[0].error);
        failed(format("line-b at %u baud", baud), two->lines[1].error);
        one_rate[baud].push_back(one->lines[0].rate());
        a_rate[baud].push_back(two->lines[0].rate());
        b_rate[baud].push_back(two->lines[1].rate());
        one_cpu[baud].push_back(one->cpu_per_transaction_us);
        two_cpu[baud].push_back(two->cpu_per_transaction_us);
      }
      // The SCADA's latency with the field line idle, saturated and unplugged: a fresh
      // site each, so that unplugging leaves nothing behind for the next.
      std::map<Field, double> p99;
      for (const auto field : {Field::idle, Field::saturated, Field::unplugged}) {
        Site site(options);
        if (field == Field::unplugged) {
          site.unplug_field();
          std::this_thread::sleep_for(200ms);  // the daemon has seen its device go
        }
        const auto cpu_before = site.daemon().cpu_us();
        const auto run = poll_scada(site, options.seconds, field == Field::saturated);
        if (field == Field::unplugged) {
          const auto log = site.daemon().log();
          // A warning line naming the field line's device and a failed write: "…ttySIM: write failed…",
          // or where the daemon reopens a lost device, "…ttySIM lost: write failed…".
          std::size_t failures = 0;
          std::istringstream lines(log);
          for (std::string line; std::getline(lines, line);)
            if (line.find("ttySIM") != std::string::npos && line.find("write failed") != std::string::npos) ++failures;
          unplugged_failures.push_back(static_cast<double>(failures));
        }
        daemon_cpu[field].push_back((site.daemon().cpu_us() - cpu_before) / 1e4 / (options.seconds + busy_warmup_s));
        failed(format("slave line, field %s", name(field)), run.error);
        if (run.latency_us.empty()) failed(format("slave line, field %s", name(field)), "no answer in the window");
        p99[field] = percentile(run.latency_us, 0.99);
        scada_p99[field].push_back(p99[field]);
        scada_p50[field].push_back(percentile(run.latency_us, 0.5));
      }
      saturated_ratio.push_back(p99[Field::saturated] / std::max(p99[Field::idle], 1.0));
      unplugged_ratio.push_back(p99[Field::unplugged] / std::max(p99[Field::idle], 1.0));
      // The TCP slave with the two lines idle against a daemon without lines, both running,
      // one loaded at a time, the order swapped every other round.
      {
        Site site(options);
        const TempDir plain_dir;
        const Daemon plain(plain_dir.path(), common_yaml(plain_dir.path()) + tcp_yaml());
        double with_lines = 0, without = 0;
        if (!options.load.empty()) {
          for (int i = 0; i < 2; ++i) {
            if ((i == 0) == (round % 2 == 0)) with_lines = bank_rate(options, site.daemon().port(), options.seconds);
            else without = bank_rate(options, plain.port(), options.seconds);
          }
        }
        if (!options.load.empty()) {
          tcp_lines.push_back(with_lines);
          tcp_plain.push_back(without);
          tcp_ratio.push_back(with_lines / without);
        }
      }
    }
  } catch (const std::exception& e) {
    host.stop();
    std::fprintf(stderr, "gateway_bench --lines: %s\n", e.what());
    return 2;
  }
  const auto late = host.stop();

  std::string report = format("Several lines bench: %d round(s) of %.1f s per run, %zu clients per master line, a read "
                              "of 10 registers (%zu + %zu bytes), slave answer delay %d ms; medians of the rounds, "
                              "their range in brackets.\n\n",
                              options.rounds, options.seconds, busy_clients, query_bytes, answer_bytes, answer_delay_ms);
  report += "| baud | line limit | one line alone | two lines: line-a | of the limit (≥ 90 %) | line-b | of the limit "
            "(≥ 90 %) | CPU per transaction, one line | two lines |\n|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const auto baud : bauds) {
    const auto limit = line_limit(baud).per_second();
    const auto a = median(a_rate[baud]), b = median(b_rate[baud]);
    report += format("| %u | %.1f/s | %s | %s | %.1f %% %s | %s | %.1f %% %s | %s | %s |\n", baud, limit,
                     range(one_rate[baud], 1, "/s").c_str(), range(a_rate[baud], 1, "/s").c_str(), 100 * a / limit,
                     verdict(a >= 0.9 * limit), range(b_rate[baud], 1, "/s").c_str(), 100 * b / limit,
                     verdict(b >= 0.9 * limit), range(one_cpu[baud], 1, " µs").c_str(),
                     range(two_cpu[baud], 1, " µs").c_str());
  }
  report += format("\nSlave line (scada, %u baud, function 4, %d registers) answering a libmodbus RTU master without "
                   "pause, the master line beside it (field, %u baud):\n\n"
                   "| field line | SCADA latency p50 | p99 | p99 ÷ idle p99 per round (≤ 1.5) | daemon CPU |\n"
                   "|---|---:|---:|---:|---:|\n",
                   scada_baud, bank_c_registers, field_baud);
  for (const auto field : {Field::idle, Field::saturated, Field::unplugged}) {
    const auto& ratio = field == Field::saturated ? saturated_ratio : unplugged_ratio;
    report += format("| %s | %s | %s | %s | %s |\n", name(field), range(scada_p50[field], 1e-3, " ms").c_str(),
                     range(scada_p99[field], 1e-3, " ms").c_str(),
                     field == Field::idle ? "" : format("%s %s", range(ratio, 1, "").c_str(), verdict(median(ratio) <= 1.5)).c_str(),
                     range(daemon_cpu[field], 1, " %").c_str());
  }
  report += format("\nIdle: no gateway client, the field line's poll every 100 ms; saturated: 8 gateway clients "
                   "beside it; unplugged: the field line's pseudo-terminal gone, each poll a failed write the daemon "
                   "logs (%s per run). Daemon CPU in %% of one core over the run.\n",
                   range(unplugged_failures, 1, "").c_str());
  if (tcp_ratio.empty()) {
    report += "\nTCP slave: not run (no --load unima-bench-load)\n";
  } else {
    report += format("\nTCP slave, function 4 on bank C (unima-bench-load, 8 connections × depth 8): %s with the two "
                     "lines idle, %s without modbus.lines; ratio %s (within 3 %%): %s\n",
                     range(tcp_lines, 1, "/s").c_str(), range(tcp_plain, 1, "/s").c_str(), range(tcp_ratio, 1, "").c_str(),
                     verdict(std::abs(median(tcp_ratio) - 1) <= 0.03));
  }
  report += "\nLoad average before: " + load_before + host_latency_line(late);
  if (!errors.empty()) report += "\nERRORS:\n" + errors;
  std::fputs(report.c_str(), stdout);
  if (!options.report.empty()) std::ofstream(options.report) << report;
  return errors.empty() ? 0 : 1;
}

}  // namespace gateway_bench
