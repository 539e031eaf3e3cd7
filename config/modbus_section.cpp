// modbus: the mode and address, the RTU line, and the master's settings and devices. The
// TCP and TLS slaves are read in config/network_sections.cpp.

#include <algorithm>
#include <array>
#include <cctype>
#include <initializer_list>
#include <iterator>
#include <optional>
#include <string_view>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "banks/number_text.hpp"
#include "config/endpoint.hpp"
#include "config/section_parsers.hpp"

namespace unima::config::sections {

namespace {

// The serial keys of modbus.rtu and of a line of modbus.lines; `key` names the line in
// messages, `other_keys` are the line's keys besides them.
RtuConfig parse_serial(ParseState& state, const YAML::Node& node, const std::string& key,
                       std::initializer_list<std::string_view> other_keys) {
  const auto& yaml = state.yaml;
  std::vector<std::string_view> allowed{"device", "baud", "parity", "stop_bits", "rs485", "low_latency", "frame_gap"};
  allowed.insert(allowed.end(), other_keys.begin(), other_keys.end());
  yaml.expect_keys(node, key, allowed);
  RtuConfig r;
  r.origin = yaml.position(node);
  if (!node["device"]) yaml.fail(node, fmt::format("{} needs the serial device, e.g. device: /dev/ttyUSB0", key));
  r.device = yaml.text(node["device"]);
  note_host_path(state, HostPath::Use::serial_device, node["device"], key + ".device", r.device);
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
void parse_gateway_unit(const YamlReader& yaml, const YAML::Node& item, const std::string& key, GatewayConfig& gateway) {
  const auto [first, last] = parse_unit_range(yaml, item, yaml.text(item), key + ".units", "3 or 2-9");
  for (unsigned unit = first; unit <= last; ++unit) gateway.units[unit] = true;
}

// `key`: "modbus.gateway", or a line's "modbus.lines.<name>.gateway".
GatewayConfig parse_gateway(const YamlReader& yaml, const YAML::Node& node, const std::string& key) {
  yaml.expect_keys(node, key, {"units", "priority", "wait", "timeout", "cache", "functions"});
  GatewayConfig gateway;
  gateway.origin = yaml.position(node);
  const auto units = node["units"];
  if (!units || !units.IsSequence() || units.size() == 0)
    yaml.fail(units ? units : node, fmt::format("{}.units must list the unit ids forwarded to the line, e.g. [2-9, 17]", key));
  // A unit listed twice is a slip that hides another (a range typed 5-5 for 5-6): named
  // at its second mention, with its first.
  std::array<std::string, 256> listed_at;  // the item's position; empty: not listed
  for (const auto& item : units) {
    GatewayConfig one;
    parse_gateway_unit(yaml, item, key, one);
    for (unsigned unit = 0; unit < one.units.size(); ++unit) {
      if (!one.units[unit]) continue;
      if (!listed_at[unit].empty())
        yaml.fail(item, fmt::format("{}.units: unit {} is listed twice (first at {})", key, unit, listed_at[unit]));
      listed_at[unit] = yaml.position(item);
      gateway.units[unit] = true;
    }
  }
  if (node["priority"]) gateway.priority = parse_allow_list(yaml, node["priority"], key + ".priority");
  if (node["wait"]) gateway.wait = positive_duration(yaml, node["wait"]);
  if (node["timeout"]) gateway.timeout = positive_duration(yaml, node["timeout"]);
  if (node["cache"]) gateway.cache = yaml.duration(node["cache"]);
  if (node["functions"]) gateway.reads_only = yaml.choice(node["functions"], {"read", "all"}) == "read";
  return gateway;
}

// Fails at the item of `gateway_node`'s units that names `unit` (else at the list).
[[noreturn]] void fail_at_unit(const YamlReader& yaml, const YAML::Node& gateway_node, const std::string& key,
                               std::uint8_t unit, std::string_view message) {
  for (const auto& item : gateway_node["units"]) {
    GatewayConfig one;
    parse_gateway_unit(yaml, item, key, one);
    if (one.routes(unit)) yaml.fail(item, message);
  }
  yaml.fail(gateway_node["units"], message);
}

// The legacy modbus.gateway (SPEC §14) forwards to the line the master owns: modbus.rtu.
void check_legacy_gateway(const YamlReader& yaml, const YAML::Node& modbus, const ModbusConfig& m) {
  const auto node = modbus["gateway"];
  if (m.mode != ModbusMode::master)
    yaml.fail(node, "modbus.gateway forwards to the line the master drives: it needs modbus.mode: master");
  if (!m.master.tcp.empty())
    yaml.fail(node, "modbus.gateway forwards RTU frames to modbus.rtu; a master driving modbus.master.tcp cannot "
                    "forward yet");
}

// A line's name goes into monitor port names (`rtu:<name>`), metrics labels and the
// status document: short, and nothing that needs quoting.
bool valid_line_name(std::string_view name) {
  return !name.empty() && name.size() <= 16 && std::all_of(name.begin(), name.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_' || c == '-';
  });
}

// An RTU slave answers one address of 1..247 (0 is broadcast, 248..255 reserved).
bool slave_address(unsigned address) { return address >= 1 && address <= 247; }

LineConfig parse_line(ParseState& state, const YAML::Node& name_node, const YAML::Node& node) {
  const auto& yaml = state.yaml;
  const auto& m = state.config.modbus;
  LineConfig line;
  line.name = yaml.text(name_node);
  if (!valid_line_name(line.name))
    yaml.fail(name_node, fmt::format("modbus.lines: '{}' is not a line name (1 to 16 of a-z, 0-9, _ and -)", line.name));
  line.key = "modbus.lines." + line.name;
  if (!node.IsMap())
    yaml.fail(node, fmt::format("{} must be a mapping, e.g. {{ device: /dev/ttyS1, baud: 9600, role: master }}", line.key));
  line.serial = parse_serial(state, node, line.key, {"role", "address", "gateway"});
  if (!node["role"])
    yaml.fail(node, fmt::format("{} needs its role: slave (a master such as a SCADA polls the bridge on it) or master "
                                "(the bridge polls the foreign slaves on it)", line.key));
  line.role = yaml.choice(node["role"], {"slave", "master"}) == "master" ? LineRole::master : LineRole::slave;
  if (const auto address = node["address"]) {
    if (line.role == LineRole::master)
      yaml.fail(address, fmt::format("{}.address is the address a slave line answers; this line is a master", line.key));
    line.address = static_cast<std::uint8_t>(yaml.number(address, 1, 247));
  } else {
    line.address = m.address;
    if (line.role == LineRole::slave && !slave_address(m.address))
      yaml.fail(node, fmt::format("modbus.address {} cannot be the address of the slave line {} (1..247): set {}.address",
                                  m.address, line.name, line.key));
  }
  if (const auto gateway = node["gateway"]) {
    if (line.role == LineRole::slave)
      yaml.fail(gateway, fmt::format("{}.gateway forwards TCP clients' requests to the slaves on a master line; this "
                                     "line is a slave", line.key));
    line.gateway = parse_gateway(yaml, gateway, line.key + ".gateway");
  }
  for (const auto& other : m.lines)
    if (other.serial.device == line.serial.device)
      yaml.fail(node["device"], fmt::format("{}.device: {} is already the device of the line {} ({}); a serial port "
                                            "carries one line", line.key, line.serial.device, other.name,
                                            other.serial.origin));
  return line;
}

// What the lines must not share (SPEC §14, §18): a unit id routed by two gateways, a unit
// that is the bridge's own address or a slave line's. `gateway_nodes` go with m.lines, in
// order (a null node: the line has no gateway).
void check_routes(const YamlReader& yaml, const ModbusConfig& m, const std::vector<YAML::Node>& gateway_nodes) {
  std::array<const LineConfig*, 256> routed_by{};
  const auto gateway_key = [](const LineConfig& line) {
    return line.key == "modbus.rtu" ? std::string("modbus.gateway") : line.key + ".gateway";
  };
  for (std::size_t n = 0; n < m.lines.size(); ++n) {
    const auto& line = m.lines[n];
    if (!line.gateway) continue;
    const auto key = gateway_key(line);
    if (line.gateway->routes(m.address))
      fail_at_unit(yaml, gateway_nodes[n], key, m.address,
                   fmt::format("{}.units: unit {} is the bridge's own modbus.address, which serves the banks: leave it out",
                               key, m.address));
    for (unsigned unit = 1; unit <= 247; ++unit) {
      if (!line.gateway->routes(static_cast<std::uint8_t>(unit))) continue;
      if (const auto* other = routed_by[unit])
        fail_at_unit(yaml, gateway_nodes[n], key, static_cast<std::uint8_t>(unit),
                     fmt::format("{}.units: unit {} is routed by the line {} too ({}); a unit id reaches one line", key,
                                 unit, other->name, other->gateway->origin));
      routed_by[unit] = &line;
    }
  }
  for (const auto& line : m.lines) {
    if (line.role != LineRole::slave || !routed_by[line.address]) continue;
    const auto& master = *routed_by[line.address];
    const auto n = static_cast<std::size_t>(&master - m.lines.data());
    const auto key = gateway_key(master);
    fail_at_unit(yaml, gateway_nodes[n], key, line.address,
                 fmt::format("{}.units: unit {} is the address of the slave line {}, which the bridge answers itself: "
                             "leave it out", key, line.address, line.name));
  }
}

void parse_lines(ParseState& state, const YAML::Node& modbus) {
  const auto& yaml = state.yaml;
  auto& m = state.config.modbus;
  const auto node = modbus["lines"];
  if (modbus["rtu"])
    yaml.fail(node, "modbus.lines and modbus.rtu are both set; modbus.rtu is the one line named rtu: move it into "
                    "modbus.lines with its role");
  if (modbus["mode"])
    yaml.fail(modbus["mode"], "modbus.mode is the role of modbus.rtu; each line of modbus.lines has its own role");
  if (modbus["gateway"])
    yaml.fail(modbus["gateway"], "modbus.gateway goes with modbus.rtu; with modbus.lines each master line has its own "
                                 "(modbus.lines.<name>.gateway)");
  if (!node.IsMap() || node.size() == 0)
    yaml.fail(node, "modbus.lines must map line names to lines, e.g. scada: { device: /dev/ttyS0, role: slave }");
  std::vector<YAML::Node> gateway_nodes;
  for (const auto& entry : node) {
    m.lines.push_back(parse_line(state, entry.first, entry.second));
    gateway_nodes.push_back(entry.second["gateway"]);
  }
  const auto* master = m.line_of(LineRole::master);
  if (master) m.mode = ModbusMode::master;
  if (master && !m.master.tcp.empty())
    yaml.fail(modbus["master"]["tcp"], fmt::format("modbus.master.tcp and the master line {} are both set; the master "
                                                   "drives one line: remove one of them", master->name));
  check_routes(yaml, m, gateway_nodes);
}

// modbus.rtu with modbus.mode (SPEC §3, §18): one line named `rtu` with the mode's role.
void parse_legacy_line(ParseState& state, const YAML::Node& modbus) {
  const auto& yaml = state.yaml;
  auto& m = state.config.modbus;
  const auto rtu = modbus["rtu"];
  if (!rtu) return;
  LineConfig line;
  line.name = "rtu";
  line.key = "modbus.rtu";
  line.role = m.mode == ModbusMode::master ? LineRole::master : LineRole::slave;
  line.serial = parse_serial(state, rtu, line.key, {});
  line.address = m.address;
  m.lines.push_back(std::move(line));
  if (m.mode == ModbusMode::slave && !slave_address(m.address))
    yaml.fail(modbus["address"] ? modbus["address"] : modbus,
              fmt::format("modbus.address {} cannot be an RTU slave's address (1..247)", m.address));
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
  yaml.expect_keys(node, "modbus", {"mode", "address", "tcp", "tls", "rtu", "lines", "readable_write_banks", "extensions",
                                     "master", "gateway"});
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
  if (!node["lines"]) parse_legacy_line(state, node);
  if (node["master"]) parse_master(state, node["master"]);
  if (node["lines"]) {
    parse_lines(state, node);
    return;
  }
  std::optional<GatewayConfig> gateway;
  if (node["gateway"]) gateway = parse_gateway(yaml, node["gateway"], "modbus.gateway");
  if (m.mode == ModbusMode::master) {
    // SPEC §3: in master mode the RTU line belongs to the master; a TCP target is the extension.
    if (m.lines.empty() && m.master.tcp.empty())
      yaml.fail(node["mode"] ? node["mode"] : node,
                "master mode needs the line to drive: modbus.rtu, or modbus.master.tcp (host:port)");
    if (!m.lines.empty() && !m.master.tcp.empty())
      yaml.fail(node["master"]["tcp"], "modbus.master.tcp and modbus.rtu are both set; the master drives one "
                                       "line: remove one of them");
  }
  if (!gateway) return;
  check_legacy_gateway(yaml, node, m);
  m.lines.front().gateway = std::move(gateway);  // master mode on modbus.rtu, checked above
  check_routes(yaml, m, {node["gateway"]});
}

}  // namespace unima::config::sections
