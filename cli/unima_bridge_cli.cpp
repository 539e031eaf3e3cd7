// unima-bridge: the operator's command line (SPEC §8).

#include <cstdio>
#include <string>
#include <string_view>
#include <vector>

#include <fmt/format.h>

#include "banks/table_reference.hpp"
#include "check/check_config.hpp"
#include "config/config.hpp"
#include "config/register_map.hpp"
#include "cli/master_format.hpp"
#include "cli/register_map_format.hpp"
#include "cli/cli_monitor.hpp"
#include "cli/cli_config.hpp"
#include "cli/cli_status.hpp"

namespace {

// One entry per subcommand: the top-level --help lists them all, and `SUB --help` prints
// its own entry, so the two never say different things (packaging/man_vs_help.py checks
// the man page against both).
struct Command {
  std::string_view name;
  std::string_view synopsis;
  std::string_view about;  // lines after the first are indented under it
};

constexpr Command commands[] = {
    {"check", "--config FILE",
     "validate a config; exit 0 when it is good, 1 with the errors when not;\n"
     "in master mode also the merge plan and the estimated bus load"},
    {"map", "--config FILE [--format table|csv|json] [--bom] [--no-reserved] [--pairs halves|uint32]",
     "every register the config serves: address, its PLC-style input (3xxxx) and\n"
     "holding (4xxxx) register numbers, bank, access, unit, scale, identifier and\n"
     "label, a row per byte of a byte pair; csv and json add offset, kind, source,\n"
     "data type, part, bits, partner and word order. --bom starts the csv with a\n"
     "UTF-8 byte order mark (Excel); --no-reserved leaves the reserves out;\n"
     "--pairs uint32 lists a 32-bit pair as one row in place of its halves"},
    {"tables", "", "the reference of every device table, in Markdown (docs/registers.md)"},
    {"status", "[-w|--watch] [--json] [--socket PATH | --config FILE]",
     "the front panel of the running daemon: mode, activity, Error, D_N/S_N on-line,\n"
     "capture indicators, counters"},
    {"monitor", "[-f|--follow] [-n|--lines N] [--filter EXPR] [--json | --pcap OUT] [--config FILE] [LOG]",
     "read, filter and follow the monitor log (one line per Modbus transaction),\n"
     "or turn it into a pcap file for Wireshark"},
    {"config", "apply FILE | show | history | revert [--json] [--timeout S] [--socket PATH | --config FILE]",
     "change the running daemon's config: apply FILE checks it, reloads and keeps it\n"
     "once its probe passed (else goes back); show, history; revert to the operator's\n"
     "file. The operator's file is never written"},
    {"profiles", "[ID]", "the device profiles of foreign slaves for master mode; with ID, its points"},
};

std::string synopsis_line(const Command& command) {
  return fmt::format("unima-bridge {}{}{}", command.name, command.synopsis.empty() ? "" : " ", command.synopsis);
}

std::string about_text(const Command& command) {
  std::string text = fmt::format("  {:<10}", command.name);
  for (const char c : command.about) text += c == '\n' ? std::string("\n            ") : std::string(1, c);
  return text + "\n";
}

std::string usage_text() {
  std::string text;
  for (const auto& command : commands) text += fmt::format("{}{}\n", text.empty() ? "usage: " : "       ", synopsis_line(command));
  text += "       unima-bridge --version | -h|--help\n\n";
  for (const auto& command : commands) text += about_text(command);
  return text +
         "\nunima-bridge status --help, monitor --help and config --help describe their options; man unima-bridge(1)\n"
         "describes them all.\n";
}

/// `unima-bridge SUB --help` for the subcommands without options of their own to explain.
std::string command_help(const Command& command) {
  return fmt::format("usage: {}\n\n{}\nman unima-bridge(1) says more.\n", synopsis_line(command), about_text(command));
}

const Command* command_named(std::string_view name) {
  for (const auto& command : commands)
    if (command.name == name) return &command;
  return nullptr;
}

bool asks_for_help(const std::vector<std::string>& args) {
  return args.size() > 1 && (args[1] == "--help" || args[1] == "-h");
}

int check(const std::string& path) {
  try {
    const auto config = unima::config::load_file(path);
    // What the daemon meets at start, checked as its remote changes are checked (check/).
    unima::check::check_config(config);
    const auto map = unima::config::address_map(config);
    for (const auto& warning : unima::config::warnings(config)) fmt::print(stderr, "{}\n", warning);
    fmt::print("{}: OK\n", path);
    for (const auto& window : map.windows())
      fmt::print("  0x{:04X}..0x{:04X}  {}\n", window.first, window.end() - 1, window.name);
    fmt::print("{}", unima::cli::format_lines(config));
    if (config.modbus.mode == unima::config::ModbusMode::master) fmt::print("{}", unima::cli::format_master_plan(config));
    return 0;
  } catch (const std::exception& e) {
    fmt::print(stderr, "{}\n", e.what());
    return 1;
  }
}

// The options every config-reading command takes: --config FILE, and map's own.
struct Options {
  std::string config;
  unima::cli::MapOutput output;
  unima::config::MapShape shape{.bytes_apart = true};
  std::string error;
};

int map(const Options& options) {
  try {
    const auto config = unima::config::load_file(options.config);
    const unima::cli::ServedFunctions served{config.modbus.extensions.function_3};
    const auto rows = unima::config::register_map(config, options.shape);
    fmt::print("{}", unima::cli::format_register_map(rows, options.output, served));
    return 0;
  } catch (const std::exception& e) {
    fmt::print(stderr, "{}\n", e.what());
    return 1;
  }
}

Options parse_options(const std::vector<std::string>& args, bool is_map) {
  Options options;
  for (std::size_t i = 1; i < args.size(); ++i) {
    std::string value;
    const auto& arg = args[i];
    const auto take = [&](const std::string& name) {
      if (arg == name && i + 1 < args.size()) return value = args[++i], true;
      if (arg.starts_with(name + "=")) return value = arg.substr(name.size() + 1), true;
      return false;
    };
    if (take("--config")) {
      options.config = value;
    } else if (is_map && take("--format")) {
      if (value == "table") options.output.format = unima::cli::MapFormat::table;
      else if (value == "csv") options.output.format = unima::cli::MapFormat::csv;
      else if (value == "json") options.output.format = unima::cli::MapFormat::json;
      else return options.error = "unknown format '" + value + "' (table, csv or json)", options;
    } else if (is_map && take("--pairs")) {
      if (value == "halves") options.shape.pairs_joined = false;
      else if (value == "uint32") options.shape.pairs_joined = true;
      else return options.error = "unknown --pairs '" + value + "' (halves or uint32)", options;
    } else if (is_map && arg == "--bom") {
      options.output.byte_order_mark = true;
    } else if (is_map && arg == "--no-reserved") {
      options.shape.reserves = false;
    } else {
      return options.error = "unknown argument '" + arg + "'", options;
    }
  }
  if (options.config.empty()) options.error = "--config FILE is required";
  else if (options.output.byte_order_mark && options.output.format != unima::cli::MapFormat::csv)
    options.error = "--bom is for --format csv only (a byte order mark for Excel)";
  return options;
}

}  // namespace

int main(int argc, char** argv) {
  const std::vector<std::string> args(argv + 1, argv + argc);
  const auto usage = usage_text();
  if (args.empty() || args[0] == "--help" || args[0] == "-h") {
    std::fputs(usage.c_str(), args.empty() ? stderr : stdout);
    return args.empty() ? 2 : 0;
  }
  if (args[0] == "--version") {
    std::puts("unima-bridge " UNIMA_VERSION);
    return 0;
  }
  // status and monitor explain their own options (cli_status, cli_monitor).
  if (const auto* command = command_named(args[0]); command && asks_for_help(args) && args[0] != "status" &&
                                                    args[0] != "monitor" && args[0] != "config") {
    fmt::print("{}", command_help(*command));
    return 0;
  }
  if (args[0] == "check" || args[0] == "map") {
    const bool is_map = args[0] == "map";
    const auto options = parse_options(args, is_map);
    if (!options.error.empty()) {
      std::fprintf(stderr, "unima-bridge %s: %s\n%s", args[0].c_str(), options.error.c_str(), usage.c_str());
      return 2;
    }
    return is_map ? map(options) : check(options.config);
  }
  if (args[0] == "profiles") {
    const auto text = unima::cli::format_profiles(args.size() > 1 ? args[1] : "");
    if (text.empty()) {
      std::fprintf(stderr, "unima-bridge profiles: no profile '%s'\n", args[1].c_str());
      return 1;
    }
    fmt::print("{}", text);
    return 0;
  }
  if (args[0] == "tables") {
    fmt::print("{}", unima::banks::tables_markdown());
    return 0;
  }
  if (args[0] == "status") return unima::cli::status_command({args.begin() + 1, args.end()});
  if (args[0] == "config") return unima::cli::config_command({args.begin() + 1, args.end()});
  if (args[0] == "monitor") return unima::cli::monitor_command({args.begin() + 1, args.end()});
  std::fprintf(stderr, "unima-bridge: unknown command '%s'\n%s", args[0].c_str(), usage.c_str());
  return 2;
}
