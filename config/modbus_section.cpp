// modbus: the mode and address, the RTU line, and the master's settings and devices. The
// TCP and TLS slaves are read in config/network_sections.cpp.

#include <algorithm>
#include <array>
#include <cctype>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "banks/number_text.hpp"
#include "config/endpoint.hpp"
#include "config/section_parsers.hpp"

namespace unima::config::sections {

namespace {

RtuConfig parse_rtu_line(ParseState& state, const YAML::Node& node) {
  const auto& yaml = state.yaml;
  yaml.expect_keys(node, "modbus.rtu", {"device", "baud", "parity", "stop_bits", "rs485", "low_latency", "frame_gap"});
  RtuConfig r;
  r.origin = yaml.position(node);
  if (!node["device"]) yaml.fail(node, "modbus.rtu needs the serial device, e.g. device: /dev/ttyUSB0");
  r.device = yaml.text(node["device"]);
  note_host_path(state, HostPath::Use::serial_device, node["device"], "modbus.rtu.device", r.device);
  if (const auto baud = node["baud"]) {
    r.baud = static_cast<unsigned>(yaml.number(baud, 0, 115200));
    // The seed's rates (4800..19200) and the usual ones above, up to 115200 (SPEC §3).
    static constexpr unsigned rates[] = {1200, 2400, 4800, 9600, 14400, 19200, 38400, 57600, 115200};
    if (std::find(std::begin(rates), std::end(rates), r.baud) == std::end(rates))
      yaml.fail(baud, fmt::format("{} baud is not supported (1200, 2400, 4800, 9600, 14400, 19200, 38400, "
                                  "57600, 115200)", r.baud));
  }
  if (node["parity"]) {
    const auto p = yaml.choice(node["parity"], {"none", "even", "odd"});
    r.parity = p == "even" ? Parity::even : p == "odd" ? Parity::odd : Parity::none;
  }
  if (node["stop_bits"]) r.stop_bits = static_cast<unsigned>(yaml.number(node["stop_bits"], 1, 2));
  if (node["rs485"]) {
    const auto d = yaml.choice(node["rs485"], {"off", "kernel", "rts"});
    r.rs485 = d == "kernel" ? Rs485Direction::kernel : d == "rts" ? Rs485Direction::rts : Rs485Direction::off;
  }
  if (node["low_latency"]) r.low_latency = yaml.boolean(node["low_latency"]);
  if (const auto gap = node["frame_gap"]; gap && yaml.text(gap) != "auto") {
    r.frame_gap = yaml.fine_duration(gap);
    // Shorter than t3.5, a pause the Modbus rule allows inside a frame would cut it.
    const auto t3_5 = line_timing(r).frame_gap;
    if (*r.frame_gap < t3_5)
      yaml.fail(gap, fmt::format("frame_gap {} µs is shorter than t3.5 at {} baud ({} µs)", r.frame_gap->count(),
                                 r.baud, t3_5.count()));
  }
  return r;
}

Duration positive_duration(const YamlReader& yaml, const YAML::Node& node) {
  const auto d = yaml.duration(node);
  if (d.count() == 0) yaml.fail(node, "must be longer than 0");
  return d;
}

MasterDeviceConfig parse_master_device(const ParseState& state, const YAML::Node& d, std::uint8_t address) {
  const auto& yaml = state.yaml;
  yaml.expect_keys(d, fmt::format("modbus.master.devices.{}", address), {"profile", "min_gap", "response_timeout", "line"});
  MasterDeviceConfig device;
  device.origin = yaml.position(d);
  if (d["profile"]) device.profile = parse_profile(state, d["profile"]);
  if (const auto line = d["line"]) {
    // The device's own setting, where it was changed from its profile's default.
    yaml.expect_keys(line, fmt::format("modbus.master.devices.{}.line", address), {"baud", "parity", "stop_bits"});
    master::SerialDefaults set;
    if (device.profile && device.profile->line) set = *device.profile->line;
    if (line["baud"]) set.baud = static_cast<unsigned>(yaml.number(line["baud"], 1200, 115200));
    if (line["parity"]) set.parity = static_cast<char>(std::toupper(yaml.choice(line["parity"], {"none", "even", "odd"})[0]));
    if (line["stop_bits"]) set.stop_bits = static_cast<unsigned>(yaml.number(line["stop_bits"], 1, 2));
    device.line = set;
  }
  if (d["min_gap"]) device.min_gap = yaml.duration(d["min_gap"]);
  if (d["response_timeout"]) device.response_timeout = positive_duration(yaml, d["response_timeout"]);
  return device;
}

void parse_master(ParseState& state, const YAML::Node& node) {
  const auto& yaml = state.yaml;
  yaml.expect_keys(node, "modbus.master",
                   {"tcp", "response_timeout", "retries", "merge_gap", "max_read_registers", "stale_after",
                    "degrade_after", "backoff", "backoff_max", "min_gap", "devices"});
  auto& m = state.config.modbus.master;
  m.origin = yaml.position(node);
  if (node["tcp"]) {
    m.tcp = yaml.text(node["tcp"]);
    auto target = parse_host_port(m.tcp, HostRule::address_or_name, PortRule::nonzero);
    if (auto* error = std::get_if<std::string>(&target)) yaml.fail(node["tcp"], *error);
    m.tcp_target = std::get<HostPort>(std::move(target));
  }
  if (node["response_timeout"]) m.response_timeout = positive_duration(yaml, node["response_timeout"]);
  if (node["retries"]) m.retries = static_cast<unsigned>(yaml.number(node["retries"], 0, 5));
  if (node["merge_gap"]) m.merge_gap = static_cast<unsigned>(yaml.number(node["merge_gap"], 0, 124));
  if (node["max_read_registers"])
    m.max_read_registers = static_cast<unsigned>(yaml.number(node["max_read_registers"], 1, 125));
  if (node["stale_after"]) m.stale_after = positive_duration(yaml, node["stale_after"]);
  if (node["degrade_after"]) m.degrade_after = static_cast<unsigned>(yaml.number(node["degrade_after"], 1, 100));
  if (node["backoff"]) m.backoff = positive_duration(yaml, node["backoff"]);
  if (node["backoff_max"]) m.backoff_max = positive_duration(yaml, node["backoff_max"]);
  if (m.backoff_max < m.backoff)
    yaml.fail(node["backoff_max"] ? node["backoff_max"] : node["backoff"], "backoff_max must not be shorter than backoff");
  if (node["min_gap"]) m.min_gap = yaml.duration(node["min_gap"]);
  if (const auto devices = node["devices"]) {
    if (!devices.IsMap())
      yaml.fail(devices, "modbus.master.devices must map Modbus addresses to { profile, min_gap, response_timeout }");
    for (const auto& entry : devices) {
      const auto address = static_cast<std::uint8_t>(yaml.number(entry.first, 1, 247));
      m.devices[address] = parse_master_device(state, entry.second, address);
    }
  }
}

// One item of modbus.gateway.units: an id, or a range "2-9".
void parse_gateway_unit(const YamlReader& yaml, const YAML::Node& item, GatewayConfig& gateway) {
  const auto [first, last] = parse_unit_range(yaml, item, yaml.text(item), "modbus.gateway.units", "3 or 2-9");
  for (unsigned unit = first; unit <= last; ++unit) gateway.units[unit] = true;
}

GatewayConfig parse_gateway(const YamlReader& yaml, const YAML::Node& node) {
  yaml.expect_keys(node, "modbus.gateway", {"units", "priority", "wait", "timeout", "cache", "functions"});
  GatewayConfig gateway;
  gateway.origin = yaml.position(node);
  const auto units = node["units"];
  if (!units || !units.IsSequence() || units.size() == 0)
    yaml.fail(units ? units : node, "modbus.gateway.units must list the unit ids forwarded to the line, e.g. [2-9, 17]");
  // A unit listed twice is a slip that hides another (a range typed 5-5 for 5-6): named
  // at its second mention, with its first.
  std::array<std::string, 256> listed_at;  // the item's position; empty: not listed
  for (const auto& item : units) {
    GatewayConfig one;
    parse_gateway_unit(yaml, item, one);
    for (unsigned unit = 0; unit < one.units.size(); ++unit) {
      if (!one.units[unit]) continue;
      if (!listed_at[unit].empty())
        yaml.fail(item, fmt::format("modbus.gateway.units: unit {} is listed twice (first at {})", unit, listed_at[unit]));
      listed_at[unit] = yaml.position(item);
      gateway.units[unit] = true;
    }
  }
  if (node["priority"]) gateway.priority = parse_allow_list(yaml, node["priority"], "modbus.gateway.priority");
  if (node["wait"]) gateway.wait = positive_duration(yaml, node["wait"]);
  if (node["timeout"]) gateway.timeout = positive_duration(yaml, node["timeout"]);
  if (node["cache"]) gateway.cache = yaml.duration(node["cache"]);
  if (node["functions"]) gateway.reads_only = yaml.choice(node["functions"], {"read", "all"}) == "read";
  return gateway;
}

// SPEC §14: the gateway forwards to the line the master owns, and never the bridge's own
// unit id, which keeps serving the banks.
void check_gateway(const YamlReader& yaml, const YAML::Node& modbus, const ModbusConfig& m) {
  const auto node = modbus["gateway"];
  if (m.mode != ModbusMode::master)
    yaml.fail(node, "modbus.gateway forwards to the line the master drives: it needs modbus.mode: master");
  if (!m.master.tcp.empty())
    yaml.fail(node, "modbus.gateway forwards RTU frames to modbus.rtu; a master driving modbus.master.tcp cannot "
                    "forward yet");
  if (!m.gateway->routes(m.address)) return;
  const auto message = fmt::format("modbus.gateway.units: unit {} is the bridge's own modbus.address, which serves the "
                                   "banks: leave it out",
                                   m.address);
  // At the item that names it.
  for (const auto& item : node["units"]) {
    GatewayConfig one;
    parse_gateway_unit(yaml, item, one);
    if (one.routes(m.address)) yaml.fail(item, message);
  }
  yaml.fail(node["units"], message);
}

}  // namespace

// 0 is the broadcast and 248..255 are reserved: no slave on a line has them.
std::pair<std::uint8_t, std::uint8_t> parse_unit_range(const YamlReader& yaml, const YAML::Node& item,
                                                       std::string_view written, std::string_view key,
                                                       std::string_view example) {
  const auto dash = written.find('-');
  const auto bound = [&](std::string_view part) {
    const auto value = banks::parse_number(std::string(part));
    if (!value)
      yaml.fail(item, fmt::format("{}: '{}' is not a unit id or a range of them (write e.g. {})", key, yaml.text(item),
                                  example));
    if (*value < 1 || *value > 247) yaml.fail(item, fmt::format("{}: unit {} is outside 1..247", key, *value));
    return static_cast<std::uint8_t>(*value);
  };
  const auto first = bound(written.substr(0, dash));
  const auto last = dash == std::string_view::npos ? first : bound(written.substr(dash + 1));
  if (last < first) yaml.fail(item, fmt::format("{}: the range {} ends before it begins", key, written));
  return {first, last};
}

const master::DeviceProfile* parse_profile(const ParseState& state, const YAML::Node& node) {
  const auto id = state.yaml.text(node);
  const auto* found = master::find_profile(id);
  if (!found)
    state.yaml.fail(node, fmt::format("unknown device profile '{}' (known: {})", id, fmt::join(master::profile_ids(), ", ")));
  return found;
}

void parse_modbus(ParseState& state, const YAML::Node& node) {
  const auto& yaml = state.yaml;
  yaml.expect_keys(node, "modbus", {"mode", "address", "tcp", "tls", "rtu", "readable_write_banks", "extensions", "master",
                                     "gateway"});
  auto& m = state.config.modbus;
  if (node["mode"]) {
    const auto mode = yaml.choice(node["mode"], {"slave", "master"});
    m.mode = mode == "master" ? ModbusMode::master : ModbusMode::slave;
  }
  if (node["address"]) m.address = static_cast<std::uint8_t>(yaml.number(node["address"], 0, 255));
  if (node["readable_write_banks"]) m.readable_write_banks = yaml.boolean(node["readable_write_banks"]);
  if (const auto ext = node["extensions"]) {
    yaml.expect_keys(ext, "modbus.extensions", {"function_3", "function_16", "function_43"});
    if (ext["function_3"]) m.extensions.function_3 = yaml.boolean(ext["function_3"]);
    if (ext["function_16"]) m.extensions.function_16 = yaml.boolean(ext["function_16"]);
    if (ext["function_43"]) m.extensions.function_43 = yaml.boolean(ext["function_43"]);
  }
  if (node["tcp"]) m.tcp = parse_modbus_tcp(state, node["tcp"]);
  if (node["tls"]) m.tls = parse_modbus_tls(state, node["tls"]);
  if (node["rtu"]) m.rtu = parse_rtu_line(state, node["rtu"]);
  // An RTU slave answers one address of 1..247 (0 is broadcast, 248..255 reserved).
  if (m.rtu && m.mode == ModbusMode::slave && (m.address < 1 || m.address > 247))
    yaml.fail(node["address"] ? node["address"] : node,
              fmt::format("modbus.address {} cannot be an RTU slave's address (1..247)", m.address));
  if (node["master"]) parse_master(state, node["master"]);
  if (node["gateway"]) m.gateway = parse_gateway(yaml, node["gateway"]);
  if (m.mode == ModbusMode::master) {
    // SPEC §3: in master mode the RTU line belongs to the master; a TCP target is the extension.
    if (!m.rtu && m.master.tcp.empty())
      yaml.fail(node["mode"] ? node["mode"] : node,
                "master mode needs the line to drive: modbus.rtu, or modbus.master.tcp (host:port)");
    if (m.rtu && !m.master.tcp.empty())
      yaml.fail(node["master"]["tcp"], "modbus.master.tcp and modbus.rtu are both set; the master drives one "
                                       "line: remove one of them");
  }
  if (m.gateway) check_gateway(yaml, node, m);
}

}  // namespace unima::config::sections
