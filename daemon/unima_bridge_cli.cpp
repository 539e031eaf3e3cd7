// unima-bridge: the operator's command line (SPEC §8).

#include <cstdio>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "banks/bank_id.hpp"
#include "config/config.hpp"
#include "daemon/cli_monitor.hpp"
#include "daemon/cli_status.hpp"

namespace {

constexpr const char* usage =
    "usage: unima-bridge check --config FILE\n"
    "       unima-bridge status [--watch] [--json] [--socket PATH | --config FILE]\n"
    "       unima-bridge monitor [--follow] [--filter EXPR] [--json] [--config FILE] [LOG]\n"
    "\n"
    "  check    validate a config; exit 0 when it is good, 1 with the errors when not\n"
    "  status   the front panel of the running daemon: mode, activity, Error, D_N/S_N on-line,\n"
    "           capture indicators, counters\n"
    "  monitor  read, filter and follow the monitor log (one line per Modbus transaction)\n";

int check(const std::string& path) {
  try {
    const auto config = unima::config::load_file(path);
    const auto map = unima::config::address_map(config);
    fmt::print("{}: OK\n", path);
    for (const auto& window : map.windows())
      fmt::print("  0x{:04X}..0x{:04X}  {}\n", window.first, window.end() - 1, window.name);
    return 0;
  } catch (const std::exception& e) {
    fmt::print(stderr, "{}\n", e.what());
    return 1;
  }
}

}  // namespace

int main(int argc, char** argv) {
  const std::vector<std::string> args(argv + 1, argv + argc);
  if (args.empty() || args[0] == "--help" || args[0] == "-h") {
    std::fputs(usage, args.empty() ? stderr : stdout);
    return args.empty() ? 2 : 0;
  }
  if (args[0] == "--version") {
    std::puts("unima-bridge " UNIMA_VERSION);
    return 0;
  }
  if (args[0] == "check") {
    std::string path;
    for (std::size_t i = 1; i < args.size(); ++i) {
      if (args[i] == "--config" && i + 1 < args.size()) path = args[++i];
      else if (args[i].starts_with("--config=")) path = args[i].substr(9);
      else {
        std::fprintf(stderr, "unima-bridge check: unknown argument '%s'\n%s", args[i].c_str(), usage);
        return 2;
      }
    }
    if (path.empty()) {
      std::fputs(usage, stderr);
      return 2;
    }
    return check(path);
  }
  if (args[0] == "status") return unima::daemon::status_command({args.begin() + 1, args.end()});
  if (args[0] == "monitor") return unima::daemon::monitor_command({args.begin() + 1, args.end()});
  std::fprintf(stderr, "unima-bridge: unknown command '%s'\n%s", args[0].c_str(), usage);
  return 2;
}
