// unima-bridged: the UnimaBUS / Modbus gateway daemon (SPEC §8). Runs in the foreground;
// SIGHUP reloads the config, SIGTERM and SIGINT stop it.

#include <malloc.h>
#include <systemd/sd-daemon.h>

#include <csignal>
#include <cstdio>
#include <cstring>
#include <string>

#include <spdlog/spdlog.h>

#include "config/config.hpp"
#include "platform/asio.hpp"
#include "app/bridge.hpp"
#include "io/peer_warning_reports.hpp"
#include "platform/logging.hpp"
#include "platform/watchdog.hpp"

namespace {

constexpr const char* usage =
    "usage: unima-bridged --config FILE\n"
    "       unima-bridged --version | -h|--help\n";

// Loading a config parses YAML into many short-lived nodes; glibc keeps the pages they
// freed, about half of the heap after start-up. The daemon then runs for months on a small
// steady heap, so it gives them back once the new config serves (issue #8's RSS).
void release_parser_memory() { malloc_trim(0); }

void wait_for_signals(unima::asio::signal_set& signals, unima::app::Bridge& bridge,
                      unima::platform::Watchdog& watchdog, unima::asio::io_context& io, const std::string& config_path) {
  signals.async_wait([&](const boost::system::error_code& ec, int signal) {
    if (ec) return;
    if (signal == SIGHUP) {
      // sd_notify(3): systemd shows the unit "reloading" until READY=1 comes back.
      sd_notify(0, "RELOADING=1");
      spdlog::info("SIGHUP: reloading {}", config_path);
      std::string status = "STATUS=running; reloaded " + config_path;
      try {
        auto config = unima::config::load_file(config_path);
        // The level is part of the config: it changes only when the whole reload commits,
        // so a refused config leaves the running level as well.
        const auto level = config.log.level;
        bridge.reload(std::move(config));
        unima::platform::set_log_level(level);
        release_parser_memory();
      } catch (const std::exception& e) {
        spdlog::error("reload failed, the running config stays: {}", e.what());
        status = std::string("STATUS=reload failed, running the previous config: ") + e.what();
      }
      sd_notify(0, ("READY=1\n" + status).c_str());
      wait_for_signals(signals, bridge, watchdog, io, config_path);
      return;
    }
    spdlog::info("{}: stopping", signal == SIGTERM ? "SIGTERM" : "SIGINT");
    sd_notify(0, "STOPPING=1");
    watchdog.stop();
    bridge.stop();
    io.stop();
  });
}

}  // namespace

int main(int argc, char** argv) {
  std::string config_path;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--config" && i + 1 < argc) {
      config_path = argv[++i];
    } else if (arg.starts_with("--config=")) {
      config_path = arg.substr(9);
    } else if (arg == "--help" || arg == "-h") {
      std::fputs(usage, stdout);
      return 0;
    } else if (arg == "--version") {
      std::puts("unima-bridged " UNIMA_VERSION);
      return 0;
    } else {
      std::fprintf(stderr, "unima-bridged: unknown argument '%s'\n%s", arg.c_str(), usage);
      return 2;
    }
  }
  if (config_path.empty()) {
    std::fputs(usage, stderr);
    return 2;
  }

  // Past a file size limit (LimitFSIZE=, ulimit -f) a log write then fails with EFBIG as on
  // a full disk — reported once, its lines lost, serving going on — instead of SIGXFSZ
  // killing the daemon.
  std::signal(SIGXFSZ, SIG_IGN);
  unima::platform::setup_logging("info");  // until the config names its level
  unima::config::Config config;
  try {
    config = unima::config::load_file(config_path);
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return 1;
  }
  unima::platform::set_log_level(config.log.level);

  try {
    // One thread runs the loop and only it touches the sockets and timers, so the reactor
    // need not lock per I/O operation; the scheduler keeps its lock, so a helper thread
    // may still post() its results to the loop. Asio treats this hint as single-threaded.
    unima::asio::io_context io(BOOST_ASIO_CONCURRENCY_HINT_UNSAFE_IO);
    unima::asio::signal_set signals(io, SIGTERM, SIGINT, SIGHUP);
    unima::app::Bridge bridge(io, std::move(config));
    unima::platform::Watchdog watchdog(io);
    unima::io::PeerWarningReports peer_warning_reports(io.get_executor());
    bridge.start();
    wait_for_signals(signals, bridge, watchdog, io, config_path);
    watchdog.start();
    release_parser_memory();
    sd_notify(0, ("READY=1\nSTATUS=running; config " + config_path).c_str());
    spdlog::info("unima-bridged " UNIMA_VERSION " running");
    io.run();
  } catch (const std::exception& e) {
    spdlog::critical("{}", e.what());
    return 1;
  }
  spdlog::info("stopped");
  return 0;
}
