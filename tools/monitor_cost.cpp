// monitor-cost: what the monitor costs per transaction, measured in-process without a
// load generator (the end-to-end benchmark is bench/'s: a config with monitor.file set).
//
//   build/tools/monitor-cost [iterations]
//
// It times, on the seed's TCP read (seed 004 §5.1):
//   serve        the CPU part of serving it: MBAP parse, request handler, MBAP write
//   observe ...  the hook a port calls (Monitor::observe) in its configurations: what the
//                event loop pays; with the log on, the writer is given time to drain
//                between batches, so no transaction is dropped and none is cheaper for it
//   format/write the writer thread's work per line: formatting, and formatting + file append;
//                then the bench's line (FC4, 64 registers, ~540 bytes) formatted and appended
//                to a rotating file in batches, in this thread's CPU time (the kernel's
//                share included), through the page cache and with whole blocks written
//                past it (monitor/file_appender.hpp)
// A real TCP transaction also costs the recv and send system calls (microseconds on
// loopback), which this leaves out: the observe/serve ratio printed is an upper bound of
// the monitor's share of the event loop's time.

#include <unistd.h>

#include <time.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include "banks/register_space.hpp"
#include "config/config.hpp"
#include "monitor/monitor.hpp"
#include "monitor/monitor_sinks.hpp"
#include "banks/write_path.hpp"
#include "modbus/mbap.hpp"
#include "monitor/monitor_line.hpp"
#include "modbus/request_handler.hpp"

namespace {

using namespace unima;
using Clock = std::chrono::steady_clock;

const std::array<std::uint8_t, 12> query = {0x12, 0x34, 0x00, 0x00, 0x00, 0x06, 0x01, 0x04, 0x00, 0x11, 0x00, 0x02};
const std::array<std::uint8_t, 13> response = {0x12, 0x34, 0x00, 0x00, 0x00, 0x07, 0x01,
                                               0x04, 0x04, 0x00, 0x50, 0x7F, 0xFF};

modbus::Transaction seed_transaction() {
  return {modbus::PortKind::tcp, "127.0.0.1:40000", std::chrono::system_clock::now(), modbus::TransactionState::done,
          query, response};
}

std::int64_t thread_cpu_ns() {
  timespec ts{};
  ::clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return std::int64_t{ts.tv_sec} * 1'000'000'000 + ts.tv_nsec;
}

template <typename F>
double ns_per_op(std::size_t n, F&& f) {
  const auto start = Clock::now();
  for (std::size_t i = 0; i < n; ++i) f(i);
  return std::chrono::duration<double, std::nano>(Clock::now() - start).count() / static_cast<double>(n);
}

double serve_cost(std::size_t n) {
  const auto config = config::load_text("banks: { D1: 0x0011 }\ndevices: { D1: { type: unigen-chp, address: 5 } }\n",
                                        "monitor-cost");
  banks::RegisterStore store(config::bank_shapes(config));
  banks::RegisterSpace space(config::address_map(config), store, banks::AccessRules{true});
  banks::WritePath model(space, nullptr);
  modbus::HandlerOptions options;
  std::array<std::uint8_t, modbus::max_pdu_size> pdu{};
  std::array<std::uint8_t, modbus::max_tcp_adu_size> out{};
  std::size_t sink = 0;
  const auto ns = ns_per_op(n, [&](std::size_t) {
    const auto adu = modbus::parse_tcp_adu(query);
    const auto length = modbus::handle_request(adu.pdu, pdu, model, options).length;
    sink += modbus::write_tcp_adu(adu.header.transaction_id, adu.header.unit_id, std::span(pdu.data(), length), out);
  });
  if (sink == 0) std::puts("?");
  return ns;
}

// observe() timed in batches; between batches (untimed) the writer catches up.
double observe_cost(monitor::Monitor& monitor, std::size_t n, std::uint64_t& dropped) {
  const auto t = seed_transaction();
  constexpr std::size_t batch = 1000;
  double total_ns = 0;
  for (std::size_t done = 0; done < n; done += batch) {
    const auto handled_before = monitor.written() + monitor.dropped();
    total_ns += ns_per_op(batch, [&](std::size_t) { monitor.observe(t); }) * batch;
    if (monitor.logging() && !monitor.filter().passes_everything()) continue;
    while (monitor.logging() && monitor.written() + monitor.dropped() < handled_before + batch)
      std::this_thread::sleep_for(std::chrono::microseconds(200));
  }
  dropped = monitor.dropped();
  return total_ns / static_cast<double>(n);
}

}  // namespace

int main(int argc, char** argv) {
  const std::size_t n = argc > 1 ? std::stoul(argv[1]) : 200'000;
  const auto dir = std::filesystem::temp_directory_path() / ("unima-monitor-cost-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);

  const double serve = serve_cost(n);
  std::printf("%-44s %8.1f ns\n", "serve (MBAP + handler, no syscalls)", serve);

  const auto report = [&](const char* what, monitor::MonitorConfig c) {
    monitor::Monitor monitor(c);
    std::uint64_t dropped = 0;
    const double ns = observe_cost(monitor, n, dropped);
    std::printf("%-44s %8.1f ns  (%4.1f %% of serve; %llu dropped)\n", what, ns, 100.0 * ns / serve,
                static_cast<unsigned long long>(dropped));
  };
  monitor::MonitorConfig off;
  report("observe, log off (counters, Ix)", off);
  monitor::MonitorConfig indicators = off;
  indicators.indicators = {{1, 0x0011}, {1, 0x0012}, {3, 0x0202}, {4, 0x0000}};
  report("observe, log off, 4 indicators", indicators);
  monitor::MonitorConfig file = off;
  file.file = (dir / "monitor.log").string();
  file.max_size = 64ull << 20;
  report("observe, log to file", file);
  monitor::MonitorConfig filtered = file;
  filtered.filter.function = 6;  // the seed's read does not pass
  report("observe, log to file, filtered out", filtered);
  monitor::MonitorConfig json = file;
  json.format = monitor::MonitorFormat::json;
  report("observe, log to file as JSON", json);

  // The writer thread's side.
  const auto t = seed_transaction();
  std::string port;
  monitor::append_port_name(port, t.port, t.peer);
  std::string line;
  const double format_text = ns_per_op(n, [&](std::size_t i) {
    line.clear();
    monitor::append_monitor_line(line, monitor::monitor_fields(t, static_cast<std::uint8_t>(i), port),
                                monitor::MonitorFormat::text);
  });
  std::printf("%-44s %8.1f ns  (%zu bytes a line)\n", "writer: format a text line", format_text, line.size());
  const double format_json = ns_per_op(n, [&](std::size_t i) {
    line.clear();
    monitor::append_monitor_line(line, monitor::monitor_fields(t, static_cast<std::uint8_t>(i), port),
                                monitor::MonitorFormat::json);
  });
  std::printf("%-44s %8.1f ns\n", "writer: format a JSON line", format_json);
  {
    monitor::RotatingFileSink sink((dir / "sink.log").string(), 10ull << 20, 2);
    constexpr std::size_t batch = 256;
    std::string lines;
    const double ns = ns_per_op(n / batch, [&](std::size_t b) {
                        lines.clear();
                        for (std::size_t i = 0; i < batch; ++i)
                          monitor::append_monitor_line(
                              lines, monitor::monitor_fields(t, static_cast<std::uint8_t>(b + i), port),
                              monitor::MonitorFormat::text);
                        sink.write(lines);
                      }) /
                      batch;
    std::printf("%-44s %8.1f ns  (=> %.0f lines/s for one writer thread)\n",
                "writer: format + append to a rotating file", ns, 1e9 / ns);
  }
  // The bench's line (FC4, 64 registers: 530 bytes) at the bench's file settings, in CPU
  // time of this thread (system time included: that is where the page cache costs).
  const std::vector<std::uint8_t> big_response = [] {
    std::vector<std::uint8_t> r = {0x12, 0x34, 0x00, 0x00, 0x00, 0x83, 0x01, 0x04, 0x80};
    for (int i = 0; i < 128; ++i) r.push_back(static_cast<std::uint8_t>(i * 37));
    return r;
  }();
  const std::array<std::uint8_t, 12> big_query = {0x12, 0x34, 0x00, 0x00, 0x00, 0x06, 0x01, 0x04, 0x11, 0x00, 0x00, 0x40};
  const modbus::Transaction big{modbus::PortKind::tcp, "127.0.0.1:40000", std::chrono::system_clock::now(),
                                modbus::TransactionState::done, big_query, big_response};
  std::string big_line;
  const double format_big = ns_per_op(n, [&](std::size_t i) {
    big_line.clear();
    monitor::append_monitor_line(big_line, monitor::monitor_fields(big, static_cast<std::uint8_t>(i), port),
                                monitor::MonitorFormat::text);
  });
  std::printf("%-44s %8.1f ns  (%zu bytes a line)\n", "writer: format a line of 64 registers", format_big,
              big_line.size());
  for (const auto route : {monitor::FileAppender::Route::page_cache, monitor::FileAppender::Route::direct_where_possible}) {
    monitor::RotatingFileSink sink((dir / "big.log").string(), 10ull << 20, 5, route);
    constexpr std::size_t batch = 2048;
    const std::size_t batches = std::max<std::size_t>(n / 200, 8);  // ~500 MB at the default n
    std::string lines;
    std::size_t bytes = 0;
    const auto cpu_start = thread_cpu_ns();
    for (std::size_t b = 0; b < batches; ++b) {
      lines.clear();
      for (std::size_t i = 0; i < batch; ++i)
        monitor::append_monitor_line(lines, monitor::monitor_fields(big, static_cast<std::uint8_t>(i), port),
                                    monitor::MonitorFormat::text);
      sink.write(lines);
      bytes += lines.size();
    }
    sink.flush();
    const double ns = static_cast<double>(thread_cpu_ns() - cpu_start) / static_cast<double>(batches * batch);
    std::printf("%-44s %8.1f ns CPU  (%zu bytes a line, %s)\n", "writer: format + append, 64 registers", ns,
                bytes / (batches * batch),
                route == monitor::FileAppender::Route::page_cache ? "through the page cache" : "direct where possible");
  }
  std::filesystem::remove_all(dir);
  return 0;
}
