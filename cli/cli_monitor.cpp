#include "cli/cli_monitor.hpp"

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <deque>
#include <optional>
#include <thread>

#include <fmt/format.h>

#include "config/config.hpp"
#include "cli/log_follower.hpp"
#include "monitor/command_filter.hpp"
#include "monitor/monitor_line.hpp"
#include "monitor/pcap_export.hpp"
#include "monitor/pcap_writer.hpp"

namespace unima::cli {

namespace {

constexpr const char* default_log = "/var/log/unima-bridge/monitor.log";
constexpr const char* monitor_usage =
    "usage: unima-bridge monitor [-f|--follow] [-n|--lines N] [--filter EXPR] [--json | --pcap OUT] [--config FILE] [LOG]\n"
    "\n"
    "  LOG            the monitor log (default: the config's monitor.file, else\n"
    "                 /var/log/unima-bridge/monitor.log)\n"
    "  -f, --follow   keep reading as lines arrive, across rotations (like tail -F);\n"
    "                 starts with the last N lines (--lines, default 10)\n"
    "  -n, --lines N  with --follow, how many of the last lines to show first\n"
    "  --config FILE  the daemon's config, for its monitor.file\n"
    "  --filter EXPR  only queries matching 'ad=3 fn=6 from=0x0200 to=0x0210'\n"
    "                 (any key may be left out; xx = any)\n"
    "  --json         print JSON lines (default: text)\n"
    "  --pcap OUT     write the transactions as a pcap file for Wireshark or tshark\n"
    "                 (OUT a file, or - for standard output: with --follow,\n"
    "                 ... --follow --pcap - | wireshark -k -i - shows them live)\n";

// How often a follower looks for new lines; an operator does not notice 100 ms.
constexpr auto follow_interval = std::chrono::milliseconds(100);

struct Options {
  bool follow = false;
  bool json = false;
  std::string pcap;  // where the pcap goes ("-": standard output); empty: text or JSON lines
  std::size_t lines = 10;
  monitor::CommandFilter filter;
  std::string config;
  std::string log;
};

// What a log line becomes: bytes for the output, or a notice for the operator (in a pcap,
// which has no place for it, a drop notice goes to standard error).
struct Rendered {
  std::string bytes;
  bool is_notice = false;
};

class Printer {
 public:
  explicit Printer(const Options& options) : options_(options) {}

  /// The line as it will be printed, or nullopt when the filter hides it.
  std::optional<Rendered> render(std::string_view line) const {
    if (!options_.pcap.empty()) return render_pcap(line);
    auto text = render_text(line);
    if (!text) return std::nullopt;
    return Rendered{std::move(*text)};
  }

 private:
  std::optional<Rendered> render_pcap(std::string_view line) const {
    const auto parsed = monitor::parse_monitor_line(line);
    if (!parsed) return std::nullopt;  // not a transaction: nothing Wireshark could show
    Rendered rendered;
    if (parsed->kind == monitor::MonitorLine::Kind::drop_notice) {
      monitor::append_drop_notice(rendered.bytes, parsed->time, parsed->dropped, monitor::MonitorFormat::text);
      rendered.is_notice = true;
      return rendered;
    }
    const auto fields = parsed->fields();
    if (!options_.filter.matches(fields.query.address, fields.query.pdu)) return std::nullopt;
    monitor::append_pcap_records(rendered.bytes, *parsed);
    if (rendered.bytes.empty()) return std::nullopt;
    return rendered;
  }

  std::optional<std::string> render_text(std::string_view line) const {
    const auto parsed = monitor::parse_monitor_line(line);
    if (!parsed) {
      // Not a monitor line: shown as it is, unless the operator asked for some lines only.
      if (!options_.filter.passes_everything() || options_.json) return std::nullopt;
      return std::string(line) + "\n";
    }
    const auto format = options_.json ? monitor::MonitorFormat::json : monitor::MonitorFormat::text;
    std::string out;
    if (parsed->kind == monitor::MonitorLine::Kind::drop_notice) {
      // Always shown: it tells the operator lines are missing.
      monitor::append_drop_notice(out, parsed->time, parsed->dropped, format);
      return out;
    }
    const auto fields = parsed->fields();
    if (!options_.filter.matches(fields.query.address, fields.query.pdu)) return std::nullopt;
    const bool is_json = !line.empty() && line.front() == '{';
    if (is_json == options_.json) return std::string(line) + "\n";  // exactly as logged
    monitor::append_monitor_line(out, fields, format);
    return out;
  }

  const Options& options_;
};

void print(std::FILE* out, const Rendered& rendered) {
  std::fwrite(rendered.bytes.data(), 1, rendered.bytes.size(), rendered.is_notice && out != stderr ? stderr : out);
}

}  // namespace

int monitor_command(const std::vector<std::string>& args) {
  Options options;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const auto& arg = args[i];
    const bool has_value = i + 1 < args.size();
    try {
      if (arg == "--follow" || arg == "-f") {
        options.follow = true;
      } else if (arg == "--json") {
        options.json = true;
      } else if (arg == "--pcap" && has_value) {
        options.pcap = args[++i];
      } else if (arg.starts_with("--pcap=")) {
        options.pcap = arg.substr(7);
      } else if ((arg == "--filter") && has_value) {
        options.filter = monitor::parse_command_filter(args[++i]);
      } else if (arg.starts_with("--filter=")) {
        options.filter = monitor::parse_command_filter(arg.substr(9));
      } else if ((arg == "--lines" || arg == "-n") && has_value) {
        options.lines = std::stoul(args[++i]);
      } else if (arg == "--config" && has_value) {
        options.config = args[++i];
      } else if (arg.starts_with("--config=")) {
        options.config = arg.substr(9);
      } else if (arg == "--help" || arg == "-h") {
        std::fputs(monitor_usage, stdout);
        return 0;
      } else if (!arg.starts_with("-") && options.log.empty()) {
        options.log = arg;
      } else {
        std::fprintf(stderr, "unima-bridge monitor: unknown argument '%s'\n%s", arg.c_str(), monitor_usage);
        return 2;
      }
    } catch (const monitor::FilterSyntaxError& e) {
      std::fprintf(stderr, "unima-bridge monitor: %s\n", e.what());
      return 2;
    } catch (const std::exception&) {
      std::fprintf(stderr, "unima-bridge monitor: '%s' is not a number of lines\n", args[i].c_str());
      return 2;
    }
  }
  if (options.json && !options.pcap.empty()) {
    std::fprintf(stderr, "unima-bridge monitor: --json and --pcap exclude each other\n%s", monitor_usage);
    return 2;
  }
  // Why this path was read: an operator who gets "No such file" needs to know which key to set.
  std::string log_origin = "the path given on the command line";
  if (options.log.empty()) {
    options.log = default_log;
    log_origin = fmt::format("the default, as no --config was given; give --config FILE to read the daemon's "
                             "monitor.file, or the log's path: unima-bridge monitor PATH");
    if (!options.config.empty()) {
      try {
        const auto config = config::load_file(options.config);
        if (!config.monitor.file.empty()) {
          options.log = config.monitor.file;
          log_origin = fmt::format("monitor.file of {}; the daemon creates it when it starts or reloads with "
                                   "that config",
                                   options.config);
        } else {
          log_origin = fmt::format(
              "the default, as {} sets no monitor.file{}; set monitor.file there (docs/configuration.md, "
              "\"monitor\") and reload the daemon, or give the log's path: unima-bridge monitor PATH",
              options.config,
              config.monitor.to_stdout ? " (its monitor goes to the daemon's standard output: journalctl -u unima-bridge)"
                                       : "");
        }
      } catch (const std::exception& e) {
        std::fprintf(stderr, "unima-bridge monitor: %s\n", e.what());
        return 1;
      }
    }
  }

  Printer printer(options);
  LogFollower follower(options.log);
  if (!follower.open()) {
    if (!options.follow) {
      std::fprintf(stderr, "unima-bridge monitor: cannot open %s: %s\n  it is %s\n", options.log.c_str(),
                   std::strerror(errno), log_origin.c_str());
      return 1;
    }
    std::fprintf(stderr, "unima-bridge monitor: waiting for %s to appear\n  it is %s\n", options.log.c_str(),
                 log_origin.c_str());
  }

  std::FILE* out = stdout;
  if (!options.pcap.empty()) {
    if (options.pcap != "-" && !(out = std::fopen(options.pcap.c_str(), "wb"))) {
      std::fprintf(stderr, "unima-bridge monitor: cannot write %s: %s\n", options.pcap.c_str(), std::strerror(errno));
      return 1;
    }
    std::string header;
    monitor::append_pcap_header(header);
    print(out, Rendered{std::move(header)});
    std::fflush(out);  // a Wireshark reading a pipe starts once it has the header
  }
  const auto finish = [&] {
    const bool flushed = std::fflush(out) == 0;
    return (out == stdout || std::fclose(out) == 0) && flushed ? 0 : 1;
  };

  if (!options.follow) {
    follower.poll([&](std::string_view line) {
      if (auto rendered = printer.render(line)) print(out, *rendered);
    });
    return finish();
  }

  // What is there already: its last lines only, as tail does.
  std::deque<Rendered> tail;
  follower.poll([&](std::string_view line) {
    if (options.lines == 0) return;
    if (auto rendered = printer.render(line)) {
      tail.push_back(std::move(*rendered));
      if (tail.size() > options.lines) tail.pop_front();
    }
  });
  for (const auto& rendered : tail) print(out, rendered);
  std::fflush(out);
  // A pcap goes to a reader record by record: Wireshark shows a frame once it has it whole.
  const bool flush_each = !options.pcap.empty();
  bool written = true;
  while (written) {
    std::this_thread::sleep_for(follow_interval);
    follower.poll([&](std::string_view line) {
      if (auto rendered = printer.render(line)) {
        print(out, *rendered);
        if (flush_each && std::fflush(out) != 0) written = false;
      }
    });
    if (std::fflush(out) != 0) written = false;  // the reader went away
  }
  finish();
  return 1;
}

}  // namespace unima::cli
