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
#include "app/config_in_force.hpp"
#include "app/remote_config_coordinator.hpp"
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

// SIGHUP re-reads the config in force (SPEC §19): the operator's file, or the remote config
// kept in force while that file is unchanged. `in_force` follows what runs. A SIGHUP that
// comes while a config from afar is being applied and probed reloads when that ends.
void reload_in_force(unima::app::Bridge& bridge, unima::app::ConfigInForce& in_force,
                     unima::app::RemoteConfigCoordinator& coordinator) {
  // sd_notify(3): systemd shows the unit "reloading" until READY=1 comes back.
  sd_notify(0, "RELOADING=1");
  const std::string config_path = in_force.operator_file;  // a copy: `in_force` is replaced below
  spdlog::info("SIGHUP: reloading {}", config_path);
  std::string status = "STATUS=running; reloaded " + config_path;
  try {
    auto next = unima::app::load_config_in_force(config_path, in_force.store_directory);
    // The level is part of the config: it changes only when the whole reload commits,
    // so a refused config leaves the running level as well.
    const auto level = next.config.log.level;
    bridge.reload(next.config);  // a copy: `in_force` keeps the config that runs
    in_force = std::move(next);
    coordinator.reloaded();
    unima::platform::set_log_level(level);
    release_parser_memory();
  } catch (const std::exception& e) {
    spdlog::error("reload failed, the running config stays: {}", e.what());
    status = std::string("STATUS=reload failed, running the previous config: ") + e.what();
  }
  sd_notify(0, ("READY=1\n" + status).c_str());
}

void wait_for_signals(unima::asio::signal_set& signals, unima::app::Bridge& bridge,
                      unima::platform::Watchdog& watchdog, unima::asio::io_context& io,
                      unima::app::ConfigInForce& in_force, unima::app::RemoteConfigCoordinator& coordinator) {
  signals.async_wait([&](const boost::system::error_code& ec, int signal) {
    if (ec) return;
    if (signal == SIGHUP) {
      coordinator.run_when_free([&] { reload_in_force(bridge, in_force, coordinator); });
      wait_for_signals(signals, bridge, watchdog, io, in_force, coordinator);
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
  // The config in force and where it came from (the operator's file, or a remote config
  // kept in the state directory), kept here for as long as the daemon runs; SIGHUP and the
  // coordinator of configs from afar (SPEC §19) change it.
  unima::app::ConfigInForce in_force;
  try {
    in_force = unima::app::load_config_in_force(config_path);
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return 1;
  }
  unima::platform::set_log_level(in_force.config.log.level);

  try {
    // One thread runs the loop and only it touches the sockets and timers, so the reactor
    // need not lock per I/O operation; the scheduler keeps its lock, so a helper thread
    // may still post() its results to the loop. Asio treats this hint as single-threaded.
    unima::asio::io_context io(BOOST_ASIO_CONCURRENCY_HINT_UNSAFE_IO);
    unima::asio::signal_set signals(io, SIGTERM, SIGINT, SIGHUP);
    unima::app::Bridge bridge(io, in_force.config);  // a copy: `in_force` keeps the config that runs
    unima::platform::Watchdog watchdog(io);
    unima::io::PeerWarningReports peer_warning_reports(io.get_executor());
    unima::app::RemoteConfigCoordinator coordinator(io, bridge, in_force);
    bridge.start();
    wait_for_signals(signals, bridge, watchdog, io, in_force, coordinator);
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
