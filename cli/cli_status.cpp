#include "cli/cli_status.hpp"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <optional>
#include <string_view>
#include <thread>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "cli/control_client.hpp"
#include "config/config.hpp"
#include "status/document.hpp"

namespace unima::cli {

namespace {

constexpr const char* status_usage =
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

enum class Paint { none, lit, problem, warning };

// `text` in the colour its meaning takes (SGR: green, bold red, yellow), when colour is on.
std::string painted(const std::string& text, Paint paint, PanelStyle style) {
  if (!style.colour || paint == Paint::none) return text;
  const char* sgr = paint == Paint::lit ? "32" : paint == Paint::problem ? "1;31" : "33";
  return fmt::format("\033[{}m{}\033[0m", sgr, text);
}

std::string led(bool on, PanelStyle style, Paint lit = Paint::lit) { return on ? painted("[*]", lit, style) : "[ ]"; }

// "1 value", "2 values": a count with its noun.
std::string counted_as(std::uint64_t count, const char* noun, const char* nouns) {
  return fmt::format("{} {}", count, count == 1 ? noun : nouns);
}

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
std::string render_gateway(const master::GatewayStatus& g, PanelStyle style) {
  std::string out = fmt::format("Gateway     units {}, wait {} ms, timeout {}, cache {}\n", g.routes, g.wait_ms,
                                g.timeout_ms ? fmt::format("{} ms", *g.timeout_ms) : std::string("the device's"),
                                g.cache_ms > 0 ? fmt::format("{} ms", g.cache_ms) : std::string("off"));
  if (g.units.empty()) return out + "  no client has asked for a unit yet\n";
  out += "  unit  requests  answered  exceptions  timeouts  bad  busy  cached  queue  wait ms last/mean/max  state\n";
  for (const auto& u : g.units) {
    const auto& w = u.wait_ms;
    const auto state = u.since ? painted("not answering since " + *u.since, Paint::problem, style) : u.state;
    out += fmt::format("  {:>4} {:>9} {:>9} {:>11} {:>9} {:>4} {:>5} {:>7} {:>6}  {:>20}  {}\n", u.unit, u.requests, u.answered,
                       u.exceptions, u.timeouts, u.bad_frames, u.busy, u.cache_hits, u.queue_depth,
                       wait_ms(w.last) + "/" + wait_ms(w.mean) + "/" + wait_ms(w.max), state);
  }
  return out;
}

}  // namespace

bool colour_on_stdout() {
  const char* no_colour = std::getenv("NO_COLOR");
  const char* term = std::getenv("TERM");
  return ::isatty(STDOUT_FILENO) != 0 && (no_colour == nullptr || *no_colour == '\0') &&
         (term == nullptr || std::string_view(term) != "dumb");
}

namespace {

// A row per RS-485 line (SPEC §18): a line that is not open, or that counts errors, is
// what an operator looks for.
std::string render_lines(const std::vector<status::LineStatus>& lines, PanelStyle style) {
  std::size_t name_width = 8, device_width = 12;
  for (const auto& l : lines) {
    name_width = std::max(name_width, l.name.size());
    device_width = std::max(device_width, l.device.size());
  }
  std::string out = fmt::format("{:<{}}  role    {:<{}}  settings     open      sent  received   errors  queue\n", "Line",
                                name_width + 2, "device", device_width);
  for (const auto& l : lines) {
    const auto errors = fmt::format("{:>8}", l.counters.errors);
    out += fmt::format("  {:<{}}  {:<6}  {:<{}}  {:<11}  {}  {:>8}  {:>8} {}  {:>5}\n", l.name, name_width, l.role,
                       l.device, device_width, l.settings, l.open ? "yes " : painted("no  ", Paint::problem, style),
                       l.counters.frames_sent, l.counters.frames_received,
                       l.counters.errors ? painted(errors, Paint::problem, style) : errors, l.queue);
  }
  return out;
}

}  // namespace

namespace {

// Where the running config came from, once a config was sent from afar (SPEC §19); a
// bridge that only ever ran its operator's file shows nothing more than before.
std::string config_in_force_lines(const std::optional<remote::ConfigStatus>& config, PanelStyle style) {
  if (!config || (config->source == "file" && !config->last)) return {};
  std::string out;
  if (config->source == "file")
    out += fmt::format("  Config    the operator's file {} (sha256 {:.12}…)\n", config->file, config->sha256);
  else
    out += fmt::format("  Config    remote config {} from {} by {} at {} (sha256 {:.12}…)\n", config->number.value_or(0),
                       config->source, config->by.value_or("?"), config->applied_at.value_or("?"), config->sha256);
  if (const auto& last = config->last) {
    const auto line = fmt::format("            last change: {} ({} by {} at {}){}{}", last->result, last->source, last->by,
                                  last->at, last->reason.empty() ? "" : ": ", last->reason);
    out += (last->result == "applied" ? line : painted(line, Paint::warning, style)) + "\n";
  }
  return out;
}

}  // namespace

std::string render_status_panel(const status::Document& s, PanelStyle style) {
  const auto& bridge = required(s.bridge, "pid");
  const auto& modbus = required(s.modbus, "modbus");
  const auto& bus = required(s.unimabus, "unimabus");
  std::string out;
  out += fmt::format("unima-bridge  {} mode  Modbus address {}  UnimaBUS address {}  up {}\n", bridge.mode,
                     bridge.modbus_address, bridge.unimabus_address, uptime(bridge.uptime_s));
  out += fmt::format("  Modbus    {}  {}\n", led(modbus.active, style), ago(modbus, "frame sent"));
  out += fmt::format("  UnimaBUS  {}  {} ({} transport)\n", led(bus.led.active, style), ago(bus.led, "telegram received"),
                     bus.transport);
  out += fmt::format("  Error     {}  {}\n", led(bridge.error, style, Paint::problem),
                     bridge.error ? painted("Modbus fault (C+0x13 bit 15; clears 2 s after the last one)", Paint::problem, style)
                                  : "no fault in the last 2 s");
  out += config_in_force_lines(s.config_in_force, style);
  out += " ";
  for (const auto& d : required(s.devices, "devices")) {
    if (!d.type) out += fmt::format(" {} -  ", d.bank);
    else out += fmt::format(" {} {} {}@{}  ", d.bank, led(d.online, style), *d.type, d.address.value_or(0));
  }
  out += "\n ";
  for (const auto& m : required(s.modules, "modules"))
    out += fmt::format(" {} {}", m.bank, led(m.online, style));
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

  if (const auto& lines = s.lines) out += render_lines(*lines, style);

  const auto& ports = s.ports;
  std::size_t port_width = 8;  // a line's port ("master:field") is wider
  for (const auto& p : ports) port_width = std::max(port_width, p.port.size());
  out += fmt::format("Port    {:{}}frames    Done  Not4Me   Err01   Err02   Err03   Err04  Timeout  clients\n", "",
                     port_width - 4);
  if (ports.empty()) out += "  none\n";
  for (const auto& p : ports) {
    // An exception or a time-out counted is what an operator looks for: in colour, once padded.
    const auto cell = [&](const char* state, std::size_t width, Paint paint) {
      const auto count = state_count(p, state);
      const auto padded = fmt::format("{:>{}}", count, width);
      return count == "-" || count == "0" ? padded : painted(padded, paint, style);
    };
    out += fmt::format("  {:<{}} {:>8} {:>7} {:>7} {} {} {} {} {} {:>8}", p.port, port_width, p.transactions, state_count(p, "Done"),
                       state_count(p, "Not4Me"), cell("Err01", 7, Paint::problem), cell("Err02", 7, Paint::problem),
                       cell("Err03", 7, Paint::problem), cell("Err04", 7, Paint::problem), cell("Timeout", 8, Paint::warning),
                       counted(p.clients));
    if (p.listen) out += "  " + *p.listen;
    out += "\n";
  }

  if (s.gateway) out += render_gateway(*s.gateway, style);

  const auto& m = required(s.monitor, "monitor");
  std::string where = m.file.value_or("");
  if (m.to_stdout) where += where.empty() ? "stdout" : " and stdout";
  if (where.empty()) {
    out += "Monitor     off (set monitor.file)\n";
  } else {
    out += fmt::format("Monitor     {} ({}), filter {}\n", where, m.format, m.filter);
    out += fmt::format("            {} written, {}\n", counted_as(m.written, "line", "lines"),
                       painted(fmt::format("{} dropped", m.dropped), m.dropped ? Paint::warning : Paint::none, style));
  }
  if (const auto& state = s.state) {
    const auto& st = *state;
    if (!st.file) out += "State       off (state.file: none): writes are not kept across a restart\n";
    else
      out += fmt::format("State       {}: {} recorded in {}, {}\n", *st.file, counted_as(st.records, "value", "values"),
                         counted_as(st.syncs, "sync", "syncs"),
                         painted(fmt::format("{} failed", st.failures), st.failures ? Paint::problem : Paint::none, style));
  }
  if (const auto& mqtt = s.mqtt) {
    const auto& q = *mqtt;
    if (q.connected)
      out += fmt::format("MQTT        connected to {} since {} as {}, topic {}/…\n", q.broker, q.since, q.client_id, q.topic);
    else
      out += painted(fmt::format("MQTT        not connected to {} since {}: {}", q.broker, q.since, q.last_error.value_or("connecting")),
                     Paint::problem, style) +
             "\n";
    out += fmt::format("            {} published, {}, {} dropped\n", counted_as(q.published, "message", "messages"),
                       counted_as(q.connections, "connection", "connections"), q.drops);
    if (q.last_takeover)
      out += painted(fmt::format("            session taken over by another client with this id {}, last at {}",
                                 counted_as(q.session_takeovers, "time", "times"), *q.last_takeover),
                     Paint::warning, style) +
             "\n";
    if (const auto& b = q.buffer)
      out += fmt::format("            history buffer {}: {} ({}) to send, {} dropped when full, {} sent\n", b->file,
                         counted_as(b->messages, "document", "documents"), counted_as(b->bytes, "byte", "bytes"), b->dropped,
                         b->history_sent);
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
      out += painted(fmt::format("Sparkplug   {} not connected to {} since {}: {}", node, p.broker, p.since,
                                 p.last_error.value_or("connecting")),
                     Paint::problem, style) +
             "\n";
    if (const auto& host = p.primary_host)
      out += fmt::format("            primary host {} {}{}\n", host->name, host->state, p.born ? "" : ": births wait for it online");
    const auto& c = p.commands;
    out += fmt::format("            {}, {} data, {}; commands {} taken, {} refused, {} malformed\n",
                       counted_as(p.births, "birth", "births"), p.data, counted_as(p.deaths, "device death", "device deaths"),
                       c.taken, c.refused, c.malformed);
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
      std::fputs(status_usage, stdout);
      return 0;
    } else {
      std::fprintf(stderr, "unima-bridge status: unknown argument '%s'\n%s", arg.c_str(), status_usage);
      return 2;
    }
  }
  if (!socket.empty() && !config_path.empty()) {
    std::fprintf(stderr, "unima-bridge status: give --socket or --config, not both\n%s", status_usage);
    return 2;
  }
  try {
    socket = control_socket_path(socket, config_path);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "unima-bridge status: %s\n", e.what());
    return 1;
  }

  const bool terminal = ::isatty(STDOUT_FILENO) != 0;
  for (bool first = true;; first = false) {
    if (!first) std::this_thread::sleep_for(watch_interval);
    const auto answer = ask_control(socket, std::nullopt, answer_timeout);
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
          out = json ? document.dump(2) + "\n" : render_status_panel(document.get<status::Document>(), {colour_on_stdout()});
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
