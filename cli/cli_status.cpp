#include "cli/cli_status.hpp"

#include <poll.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <optional>
#include <thread>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "config/config.hpp"
#include "status/document.hpp"

namespace unima::cli {

namespace {

constexpr const char* usage =
    "usage: unima-bridge status [-w|--watch] [--json] [--socket PATH | --config FILE]\n"
    "\n"
    "  shows what the Bridge's front panel shows: mode, Modbus and UnimaBUS activity, Error,\n"
    "  D_N and S_N on-line, the capture indicators, counters per port, and with\n"
    "  modbus.gateway one row per unit its clients reach\n"
    "  --config FILE  the daemon's config, for its status.socket\n"
    "  --socket PATH  the daemon's status socket (default: the config's status.socket, else\n"
    "                 /run/unima-bridge/control.sock)\n"
    "  -w, --watch    refresh every second until interrupted\n"
    "  --json         the daemon's JSON document\n";

constexpr auto answer_timeout = std::chrono::seconds(3);
constexpr auto watch_interval = std::chrono::seconds(1);

struct Answer {
  std::optional<std::string> text;
  std::string error;
};

// One document per connection: connect, read to EOF.
Answer ask(const std::string& path) {
  Answer answer;
  const int fd = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  std::strncpy(address.sun_path, path.c_str(), sizeof address.sun_path - 1);
  if (::connect(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0) {
    answer.error = fmt::format("cannot reach the daemon on {}: {}", path, std::strerror(errno));
    ::close(fd);
    return answer;
  }
  std::string text;
  const auto deadline = std::chrono::steady_clock::now() + answer_timeout;
  while (true) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
    pollfd p{fd, POLLIN, 0};
    if (left.count() <= 0 || ::poll(&p, 1, static_cast<int>(left.count())) <= 0) {
      answer.error = fmt::format("the daemon on {} did not answer within {} s", path, answer_timeout.count());
      ::close(fd);
      return answer;
    }
    char buffer[8192];
    const auto n = ::read(fd, buffer, sizeof buffer);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    text.append(buffer, static_cast<std::size_t>(n));
  }
  ::close(fd);
  answer.text = std::move(text);
  return answer;
}

std::string led(bool on) { return on ? "[*]" : "[ ]"; }

std::string ago(const status::Activity& activity, const char* what) {
  if (!activity.last_ms_ago) return fmt::format("no {} yet", what);
  return fmt::format("last {} {:.1f} s ago", what, static_cast<double>(*activity.last_ms_ago) / 1000.0);
}

std::string uptime(std::int64_t seconds) {
  return fmt::format("{}h{:02}m{:02}s", seconds / 3600, seconds / 60 % 60, seconds % 60);
}

// A port's count in the table; "-" where the port has no such figure.
std::string counted(const std::optional<std::uint64_t>& count) { return count ? std::to_string(*count) : "-"; }

std::string state_count(const status::PortStatus& port, const char* state) {
  const auto found = port.states.find(state);
  return found == port.states.end() ? "-" : std::to_string(found->second);
}

// A part the daemon always writes: its absence is an unexpected document.
template <class Part>
const Part& required(const std::optional<Part>& part, const char* key) {
  if (!part) throw MissingPart(fmt::format("it has no \"{}\"", key));
  return *part;
}

// A wait in ms as the table shows it: whole ms from 10 up, tenths below.
std::string wait_ms(double value) { return value >= 10 ? fmt::format("{:.0f}", value) : fmt::format("{:.1f}", value); }

// modbus.gateway (SPEC §14): one row per unit a client has asked for, the silent ones
// saying since when.
std::string render_gateway(const master::GatewayStatus& g) {
  std::string out = fmt::format("Gateway     units {}, wait {} ms, timeout {}, cache {}\n", g.routes, g.wait_ms,
                                g.timeout_ms ? fmt::format("{} ms", *g.timeout_ms) : std::string("the device's"),
                                g.cache_ms > 0 ? fmt::format("{} ms", g.cache_ms) : std::string("off"));
  if (g.units.empty()) return out + "  no client has asked for a unit yet\n";
  out += "  unit  requests  answered  exceptions  timeouts  bad  busy  cached  queue  wait ms last/mean/max  state\n";
  for (const auto& u : g.units) {
    const auto& w = u.wait_ms;
    const auto state = u.since ? "not answering since " + *u.since : u.state;
    out += fmt::format("  {:>4} {:>9} {:>9} {:>11} {:>9} {:>4} {:>5} {:>7} {:>6}  {:>20}  {}\n", u.unit, u.requests, u.answered,
                       u.exceptions, u.timeouts, u.bad_frames, u.busy, u.cache_hits, u.queue_depth,
                       wait_ms(w.last) + "/" + wait_ms(w.mean) + "/" + wait_ms(w.max), state);
  }
  return out;
}

}  // namespace

std::string render_status_panel(const status::Document& s) {
  const auto& bridge = required(s.bridge, "pid");
  const auto& modbus = required(s.modbus, "modbus");
  const auto& bus = required(s.unimabus, "unimabus");
  std::string out;
  out += fmt::format("unima-bridge  {} mode  Modbus address {}  UnimaBUS address {}  up {}\n", bridge.mode,
                     bridge.modbus_address, bridge.unimabus_address, uptime(bridge.uptime_s));
  out += fmt::format("  Modbus    {}  {}\n", led(modbus.active), ago(modbus, "frame sent"));
  out += fmt::format("  UnimaBUS  {}  {} ({} transport)\n", led(bus.led.active), ago(bus.led, "telegram received"),
                     bus.transport);
  out += fmt::format("  Error     {}  {}\n", led(bridge.error),
                     bridge.error ? "Modbus fault (C+0x13 bit 15; clears 2 s after the last one)" : "no fault in the last 2 s");
  out += " ";
  for (const auto& d : required(s.devices, "devices")) {
    if (!d.type) out += fmt::format(" {} -  ", d.bank);
    else out += fmt::format(" {} {} {}@{}  ", d.bank, led(d.online), *d.type, d.address.value_or(0));
  }
  out += "\n ";
  for (const auto& m : required(s.modules, "modules"))
    out += fmt::format(" {} {}", m.bank, led(m.online));
  out += "\n";

  out += "Capture indicators\n";
  const auto& indicators = required(s.indicators, "indicators");
  if (indicators.empty()) out += "  none configured (monitor.indicators)\n";
  int n = 1;
  for (const auto& i : indicators) {
    out += fmt::format("  {}  Ad={:<3} Reg=0x{:04X}  ", n++, i.address, i.reg);
    if (!i.value) out += "-\n";
    else
      out += fmt::format("0x{:04X} ({:5})  {:<5}  {}\n", *i.value, *i.value, i.access.value_or(""), i.time.value_or(""));
  }

  out += "Port        frames    Done  Not4Me   Err01   Err02   Err03   Err04  Timeout  clients\n";
  const auto& ports = s.ports;
  if (ports.empty()) out += "  none\n";
  for (const auto& p : ports) {
    out += fmt::format("  {:<8} {:>8} {:>7} {:>7} {:>7} {:>7} {:>7} {:>7} {:>8} {:>8}", p.port, p.transactions,
                       state_count(p, "Done"), state_count(p, "Not4Me"), state_count(p, "Err01"), state_count(p, "Err02"),
                       state_count(p, "Err03"), state_count(p, "Err04"), state_count(p, "Timeout"), counted(p.clients));
    if (p.listen) out += "  " + *p.listen;
    out += "\n";
  }

  if (s.gateway) out += render_gateway(*s.gateway);

  const auto& m = required(s.monitor, "monitor");
  std::string where = m.file.value_or("");
  if (m.to_stdout) where += where.empty() ? "stdout" : " and stdout";
  if (where.empty()) {
    out += "Monitor     off (set monitor.file)\n";
  } else {
    out += fmt::format("Monitor     {} ({}), filter {}\n", where, m.format, m.filter);
    out += fmt::format("            {} lines written, {} dropped\n", m.written, m.dropped);
  }
  if (const auto& state = s.state) {
    const auto& st = *state;
    if (!st.file) out += "State       off (state.file: none): writes are not kept across a restart\n";
    else
      out += fmt::format("State       {}: {} values recorded in {} syncs, {} failed\n", *st.file, st.records, st.syncs, st.failures);
  }
  if (const auto& mqtt = s.mqtt) {
    const auto& q = *mqtt;
    if (q.connected)
      out += fmt::format("MQTT        connected to {} since {} as {}, topic {}/…\n", q.broker, q.since, q.client_id, q.topic);
    else
      out += fmt::format("MQTT        not connected to {} since {}: {}\n", q.broker, q.since, q.last_error.value_or("connecting"));
    out += fmt::format("            {} messages published, {} connections, {} dropped\n", q.published, q.connections, q.drops);
    if (q.last_takeover)
      out += fmt::format("            session taken over by another client with this id {} times, last at {}\n",
                         q.session_takeovers, *q.last_takeover);
    if (const auto& b = q.buffer)
      out += fmt::format("            history buffer {}: {} documents ({} bytes) to send, {} dropped when full, {} sent\n",
                         b->file, b->messages, b->bytes, b->dropped, b->history_sent);
    else
      out += "            no history buffer (mqtt.buffer.file: none): an outage keeps only the present values\n";
  }
  if (const auto& sparkplug = s.sparkplug) {
    const auto& p = *sparkplug;
    const auto node = fmt::format("{}/{}", p.group_id, p.edge_node_id);
    if (p.connected)
      out += fmt::format("Sparkplug   {} connected to {} since {}, bdSeq {}, next seq {}\n", node, p.broker, p.since,
                         p.bdSeq ? std::to_string(*p.bdSeq) : std::string("null"), p.seq);
    else
      out += fmt::format("Sparkplug   {} not connected to {} since {}: {}\n", node, p.broker, p.since,
                         p.last_error.value_or("connecting"));
    if (const auto& host = p.primary_host)
      out += fmt::format("            primary host {} {}{}\n", host->name, host->state, p.born ? "" : ": births wait for it online");
    const auto& c = p.commands;
    out += fmt::format("            {} births, {} data, {} device deaths; commands {} taken, {} refused, {} malformed\n", p.births,
                       p.data, p.deaths, c.taken, c.refused, c.malformed);
  }
  return out;
}

int status_command(const std::vector<std::string>& args) {
  bool watch = false;
  bool json = false;
  std::string socket;
  std::string config_path;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const auto& arg = args[i];
    const bool has_value = i + 1 < args.size();
    if (arg == "--watch" || arg == "-w") watch = true;
    else if (arg == "--json") json = true;
    else if (arg == "--socket" && has_value) socket = args[++i];
    else if (arg.starts_with("--socket=")) socket = arg.substr(9);
    else if (arg == "--config" && has_value) config_path = args[++i];
    else if (arg.starts_with("--config=")) config_path = arg.substr(9);
    else if (arg == "--help" || arg == "-h") {
      std::fputs(usage, stdout);
      return 0;
    } else {
      std::fprintf(stderr, "unima-bridge status: unknown argument '%s'\n%s", arg.c_str(), usage);
      return 2;
    }
  }
  if (!socket.empty() && !config_path.empty()) {
    std::fprintf(stderr, "unima-bridge status: give --socket or --config, not both\n%s", usage);
    return 2;
  }
  if (socket.empty()) {
    socket = config::StatusConfig{}.socket;
    if (!config_path.empty()) {
      try {
        socket = config::load_file(config_path).status.socket;
      } catch (const std::exception& e) {
        std::fprintf(stderr, "unima-bridge status: %s\n", e.what());
        return 1;
      }
    }
  }

  const bool terminal = ::isatty(STDOUT_FILENO) != 0;
  for (bool first = true;; first = false) {
    if (!first) std::this_thread::sleep_for(watch_interval);
    const auto answer = ask(socket);
    std::string out;
    int code = 0;
    if (!answer.text) {
      if (!watch) {
        std::fprintf(stderr, "unima-bridge status: %s\n", answer.error.c_str());
        return 1;
      }
      out = answer.error + "\n";
    } else {
      const auto document = nlohmann::json::parse(*answer.text, nullptr, false);
      if (document.is_discarded()) {
        std::fprintf(stderr, "unima-bridge status: the daemon on %s sent no JSON document\n", socket.c_str());
        if (!watch) return 1;
        code = 1;
      } else {
        try {
          out = json ? document.dump(2) + "\n" : render_status_panel(document.get<status::Document>());
        } catch (const std::exception& e) {  // a part absent (MissingPart) or of another shape (json::exception)
          std::fprintf(stderr, "unima-bridge status: unexpected document from %s: %s\n", socket.c_str(), e.what());
          if (!watch) return 1;
          code = 1;
        }
      }
    }
    if (watch && terminal) out = "\033[H\033[2J" + out;  // redraw in place
    else if (watch && !first) out = "\n" + out;
    std::fwrite(out.data(), 1, out.size(), stdout);
    if (std::fflush(stdout) != 0) return 1;
    if (!watch) return code;
  }
}

}  // namespace unima::cli
