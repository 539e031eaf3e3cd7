#include <unistd.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "banks/table_catalog.hpp"
#include "banks/yaml_document.hpp"
#include "config/config.hpp"
#include "config/endpoint.hpp"
#include "config/socket_path.hpp"
#include "config/source_ref_parser.hpp"
#include "config/master_setup.hpp"
#include "master/plc_operand.hpp"
#include "monitor/log_path.hpp"
#include "config/yaml_reader.hpp"

namespace unima::config {

namespace {

using banks::BankId;

// systemd's StateDirectory= is where a service keeps its state; $STATE_DIRECTORY lists its
// directories separated by colons. Outside the service the state goes beside the config.
std::string default_state_file(const std::string& config_file) {
  if (const char* directories = std::getenv("STATE_DIRECTORY"); directories && *directories) {
    const std::string first(directories, std::strcspn(directories, ":"));
    return first + "/state";
  }
  return std::filesystem::path(config_file).replace_extension(".state").string();
}

class Loader {
 public:
  explicit Loader(const std::string& origin) : yaml_(origin) { config_.file = origin; }

  Config load(const YAML::Node& root) {
    if (!root.IsNull() && !root.IsMap()) yaml_.fail(root, "the config must be a mapping of sections");
    yaml_.expect_keys(root, "the config",
                      {"unimabus", "modbus", "banks", "devices", "mapping", "blocks", "log", "monitor", "status", "state",
                       "http", "mqtt"});
    for (BankId bank : banks::all_banks) config_.bank_bases[index_of(bank)] = banks::default_base(bank);
    if (root["unimabus"]) unimabus(root["unimabus"]);
    if (root["modbus"]) modbus(root["modbus"]);
    if (root["banks"]) bank_bases(root["banks"]);
    if (root["devices"]) devices(root["devices"]);
    shapes_ = bank_shapes(config_);
    if (root["mapping"]) mapping(root["mapping"]);
    if (root["blocks"]) blocks(root["blocks"]);
    if (root["log"]) log(root["log"]);
    if (root["monitor"]) monitor(root["monitor"]);
    status(root["status"], root);
    state(root["state"]);
    if (root["http"]) http(root["http"]);
    if (root["mqtt"]) mqtt(root["mqtt"]);
    validate_layout(root);
    resolve_roles();
    return std::move(config_);
  }

 private:
  // The replay transport's keys; its file is read and checked now, so that `check` and a
  // reload see a bad line before anything starts (SPEC §6).
  void replay(const YAML::Node& node) {
    auto& r = config_.unimabus.replay;
    const bool replaying = config_.unimabus.transport == TransportKind::replay;
    for (const char* key : {"file", "loop", "speed"})
      if (node[key] && !replaying) yaml_.fail(node[key], fmt::format("'{}' is a key of the replay transport", key));
    if (!replaying) return;
    if (!node["file"]) yaml_.fail(node, "the replay transport needs 'file', the recording to play");
    r.file = yaml_.text(node["file"]);
    if (node["loop"]) r.loop = yaml_.boolean(node["loop"]);
    if (node["speed"]) {
      r.speed = yaml_.decimal(node["speed"]);
      if (r.speed < 0.001 || r.speed > 1000) yaml_.fail(node["speed"], "speed must be 0.001..1000 (1 plays in real time)");
    }
    std::ifstream in(r.file, std::ios::binary);
    if (!in) yaml_.fail(node["file"], fmt::format("cannot read the recording {}: {}", r.file, std::strerror(errno)));
    std::ostringstream text;
    text << in.rdbuf();
    try {
      r.recording = std::make_shared<const unimabus::Recording>(unimabus::parse_recording(text.str(), r.file));
    } catch (const unimabus::RecordingError& e) {
      throw ConfigError(e.what());
    }
  }

  void unimabus(const YAML::Node& node) {
    yaml_.expect_keys(node, "unimabus",
                      {"address", "transport", "listen", "max_clients", "offline_after", "sim", "file", "loop", "speed",
                       "record"});
    auto& u = config_.unimabus;
    if (node["address"]) u.address = static_cast<std::uint8_t>(yaml_.number(node["address"], 0, 255));
    if (node["transport"]) {
      const auto t = yaml_.choice(node["transport"], {"sim", "feed", "replay"});
      u.transport = t == "feed" ? TransportKind::feed : t == "replay" ? TransportKind::replay : TransportKind::sim;
    }
    replay(node);
    if (const auto record = node["record"]) {
      yaml_.expect_keys(record, "unimabus.record", {"file", "max_size", "max_files"});
      if (!record["file"]) yaml_.fail(record, "unimabus.record needs the file to record to");
      u.record.file = yaml_.text(record["file"]);
      if (u.record.file.empty()) yaml_.fail(record["file"], "unimabus.record.file must name a file");
      check_log_path(record["file"], "unimabus.record.file", u.record.file);
      if (record["max_size"]) u.record.max_size = yaml_.byte_size(record["max_size"], 4096, 1ull << 40);
      if (record["max_files"]) u.record.max_files = static_cast<unsigned>(yaml_.number(record["max_files"], 1, 100));
    }
    if (node["listen"]) u.listen = yaml_.text(node["listen"]);
    if (node["max_clients"]) u.max_clients = static_cast<unsigned>(yaml_.number(node["max_clients"], 1, 1000));
    if (node["offline_after"]) {
      u.offline_after = yaml_.duration(node["offline_after"]);
      if (u.offline_after.count() == 0) yaml_.fail(node["offline_after"], "offline_after must be longer than 0");
    }
    if (const auto sim = node["sim"]) {
      yaml_.expect_keys(sim, "unimabus.sim", {"seed", "period", "io_modules"});
      if (sim["seed"]) u.sim.seed = static_cast<std::uint32_t>(yaml_.number(sim["seed"], 0, 0xFFFFFFFF));
      if (sim["period"]) {
        u.sim.period = yaml_.duration(sim["period"]);
        if (u.sim.period < Duration(10)) yaml_.fail(sim["period"], "the simulator period must be at least 10ms");
      }
      if (const auto modules = sim["io_modules"]) {
        if (!modules.IsSequence()) yaml_.fail(modules, "io_modules must be a list of slots 1..7");
        for (const auto& slot : modules) u.sim.io_modules.push_back(static_cast<unsigned>(yaml_.number(slot, 1, 7)));
      }
    }
    if (u.transport == TransportKind::feed) {
      if (u.listen.empty()) yaml_.fail(node, "the feed transport needs 'listen' (host:port or unix:/path)");
      check_listen(node["listen"]);
    } else if (node["listen"]) {
      yaml_.fail(node["listen"], "'listen' belongs to the feed transport only");
    }
  }

  void check_listen(const YAML::Node& node) {
    auto parsed = parse_listen_endpoint(config_.unimabus.listen);
    if (auto* error = std::get_if<std::string>(&parsed)) yaml_.fail(node, *error);
    auto& endpoint = config_.unimabus.listen_at = std::get<ListenEndpoint>(std::move(parsed));
    if (endpoint.is_unix()) check_socket_path(node, "unimabus.listen", endpoint.unix_path);
  }

  // Where the daemon will listen on a unix socket: nothing, or a socket it may replace
  // (config/socket_path); the daemon checks again before it removes anything.
  void check_socket_path(const YAML::Node& node, std::string_view key, const std::string& path) const {
    if (const auto conflict = socket_path_conflict(path)) yaml_.fail(node, fmt::format("{}: {}", key, *conflict));
  }

  // Where the daemon appends a log: never through a symbolic link (monitor/log_path).
  void check_log_path(const YAML::Node& node, std::string_view key, const std::string& path) const {
    if (const auto refused = monitor::refused_log_path(path)) yaml_.fail(node, fmt::format("{}: {}", key, *refused));
  }

  void modbus(const YAML::Node& node) {
    yaml_.expect_keys(node, "modbus",
                      {"mode", "address", "tcp", "tls", "rtu", "readable_write_banks", "extensions", "master"});
    auto& m = config_.modbus;
    if (node["mode"]) {
      const auto mode = yaml_.choice(node["mode"], {"slave", "master"});
      m.mode = mode == "master" ? ModbusMode::master : ModbusMode::slave;
    }
    if (node["address"]) m.address = static_cast<std::uint8_t>(yaml_.number(node["address"], 0, 255));
    if (node["readable_write_banks"]) m.readable_write_banks = yaml_.boolean(node["readable_write_banks"]);
    if (const auto ext = node["extensions"]) {
      yaml_.expect_keys(ext, "modbus.extensions", {"function_3", "function_16", "function_43"});
      if (ext["function_3"]) m.extensions.function_3 = yaml_.boolean(ext["function_3"]);
      if (ext["function_16"]) m.extensions.function_16 = yaml_.boolean(ext["function_16"]);
      if (ext["function_43"]) m.extensions.function_43 = yaml_.boolean(ext["function_43"]);
    }
    if (const auto tcp = node["tcp"]) {
      yaml_.expect_keys(tcp, "modbus.tcp", tcp_keys);
      m.tcp = tcp_slave(tcp, "modbus.tcp", TcpSlaveConfig{});
    }
    if (const auto tls = node["tls"]) m.tls = tls_slave(tls);
    if (const auto rtu = node["rtu"]) m.rtu = rtu_line(rtu);
    // An RTU slave answers one address of 1..247 (0 is broadcast, 248..255 reserved).
    if (m.rtu && m.mode == ModbusMode::slave && (m.address < 1 || m.address > 247))
      yaml_.fail(node["address"] ? node["address"] : node,
                 fmt::format("modbus.address {} cannot be an RTU slave's address (1..247)", m.address));
    if (const auto master_node = node["master"]) master(master_node);
    if (m.mode == ModbusMode::master) {
      // SPEC §3: in master mode the RTU line belongs to the master; a TCP target is the extension.
      if (!m.rtu && m.master.tcp.empty())
        yaml_.fail(node["mode"] ? node["mode"] : node,
                   "master mode needs the line to drive: modbus.rtu, or modbus.master.tcp (host:port)");
      if (m.rtu && !m.master.tcp.empty())
        yaml_.fail(node["master"]["tcp"], "modbus.master.tcp and modbus.rtu are both set; the master drives one "
                                          "line: remove one of them");
    }
  }

  void master(const YAML::Node& node) {
    yaml_.expect_keys(node, "modbus.master",
                      {"tcp", "response_timeout", "retries", "merge_gap", "max_read_registers", "stale_after",
                       "degrade_after", "backoff", "backoff_max", "min_gap", "devices"});
    auto& m = config_.modbus.master;
    m.origin = yaml_.position(node);
    const auto positive = [&](const YAML::Node& n) {
      const auto d = yaml_.duration(n);
      if (d.count() == 0) yaml_.fail(n, "must be longer than 0");
      return d;
    };
    if (node["tcp"]) {
      m.tcp = yaml_.text(node["tcp"]);
      auto target = parse_host_port(m.tcp, HostRule::address_or_name, PortRule::nonzero);
      if (auto* error = std::get_if<std::string>(&target)) yaml_.fail(node["tcp"], *error);
      m.tcp_target = std::get<HostPort>(std::move(target));
    }
    if (node["response_timeout"]) m.response_timeout = positive(node["response_timeout"]);
    if (node["retries"]) m.retries = static_cast<unsigned>(yaml_.number(node["retries"], 0, 5));
    if (node["merge_gap"]) m.merge_gap = static_cast<unsigned>(yaml_.number(node["merge_gap"], 0, 124));
    if (node["max_read_registers"])
      m.max_read_registers = static_cast<unsigned>(yaml_.number(node["max_read_registers"], 1, 125));
    if (node["stale_after"]) m.stale_after = positive(node["stale_after"]);
    if (node["degrade_after"]) m.degrade_after = static_cast<unsigned>(yaml_.number(node["degrade_after"], 1, 100));
    if (node["backoff"]) m.backoff = positive(node["backoff"]);
    if (node["backoff_max"]) m.backoff_max = positive(node["backoff_max"]);
    if (m.backoff_max < m.backoff)
      yaml_.fail(node["backoff_max"] ? node["backoff_max"] : node["backoff"], "backoff_max must not be shorter than backoff");
    if (node["min_gap"]) m.min_gap = yaml_.duration(node["min_gap"]);
    if (const auto devices = node["devices"]) {
      if (!devices.IsMap()) yaml_.fail(devices, "modbus.master.devices must map Modbus addresses to { profile, min_gap, response_timeout }");
      for (const auto& entry : devices) {
        const auto address = static_cast<std::uint8_t>(yaml_.number(entry.first, 1, 247));
        const auto& d = entry.second;
        yaml_.expect_keys(d, fmt::format("modbus.master.devices.{}", address),
                          {"profile", "min_gap", "response_timeout", "line"});
        MasterDeviceConfig device;
        device.origin = yaml_.position(d);
        if (d["profile"]) device.profile = profile(d["profile"]);
        if (const auto line = d["line"]) {
          // The device's own setting, where it was changed from its profile's default.
          yaml_.expect_keys(line, fmt::format("modbus.master.devices.{}.line", address), {"baud", "parity", "stop_bits"});
          master::SerialDefaults set;
          if (device.profile && device.profile->line) set = *device.profile->line;
          if (line["baud"]) set.baud = static_cast<unsigned>(yaml_.number(line["baud"], 1200, 115200));
          if (line["parity"]) set.parity = static_cast<char>(std::toupper(yaml_.choice(line["parity"], {"none", "even", "odd"})[0]));
          if (line["stop_bits"]) set.stop_bits = static_cast<unsigned>(yaml_.number(line["stop_bits"], 1, 2));
          device.line = set;
        }
        if (d["min_gap"]) device.min_gap = yaml_.duration(d["min_gap"]);
        if (d["response_timeout"]) device.response_timeout = positive(d["response_timeout"]);
        m.devices[address] = device;
      }
    }
  }

  const master::DeviceProfile* profile(const YAML::Node& node) const {
    const auto id = yaml_.text(node);
    const auto* found = master::find_profile(id);
    if (!found)
      yaml_.fail(node, fmt::format("unknown device profile '{}' (known: {})", id, fmt::join(master::profile_ids(), ", ")));
    return found;
  }

  RtuConfig rtu_line(const YAML::Node& node) const {
    yaml_.expect_keys(node, "modbus.rtu", {"device", "baud", "parity", "stop_bits", "rs485", "low_latency", "frame_gap"});
    RtuConfig r;
    r.origin = yaml_.position(node);
    if (!node["device"]) yaml_.fail(node, "modbus.rtu needs the serial device, e.g. device: /dev/ttyUSB0");
    r.device = yaml_.text(node["device"]);
    if (const auto baud = node["baud"]) {
      r.baud = static_cast<unsigned>(yaml_.number(baud, 0, 115200));
      // The seed's rates (4800..19200) and the usual ones above, up to 115200 (SPEC §3).
      static constexpr unsigned rates[] = {1200, 2400, 4800, 9600, 14400, 19200, 38400, 57600, 115200};
      if (std::find(std::begin(rates), std::end(rates), r.baud) == std::end(rates))
        yaml_.fail(baud, fmt::format("{} baud is not supported (1200, 2400, 4800, 9600, 14400, 19200, 38400, "
                                     "57600, 115200)", r.baud));
    }
    if (node["parity"]) {
      const auto p = yaml_.choice(node["parity"], {"none", "even", "odd"});
      r.parity = p == "even" ? Parity::even : p == "odd" ? Parity::odd : Parity::none;
    }
    if (node["stop_bits"]) r.stop_bits = static_cast<unsigned>(yaml_.number(node["stop_bits"], 1, 2));
    if (node["rs485"]) {
      const auto d = yaml_.choice(node["rs485"], {"off", "kernel", "rts"});
      r.rs485 = d == "kernel" ? Rs485Direction::kernel : d == "rts" ? Rs485Direction::rts : Rs485Direction::off;
    }
    if (node["low_latency"]) r.low_latency = yaml_.boolean(node["low_latency"]);
    if (const auto gap = node["frame_gap"]; gap && yaml_.text(gap) != "auto") {
      r.frame_gap = yaml_.fine_duration(gap);
      // Shorter than t3.5, a pause the Modbus rule allows inside a frame would cut it.
      const auto t3_5 = line_timing(r).frame_gap;
      if (*r.frame_gap < t3_5)
        yaml_.fail(gap, fmt::format("frame_gap {} µs is shorter than t3.5 at {} baud ({} µs)", r.frame_gap->count(),
                                    r.baud, t3_5.count()));
    }
    return r;
  }

  void bank_bases(const YAML::Node& node) {
    if (!node.IsMap()) yaml_.fail(node, "banks must map bank names (A, B, C, D1..D4, S1..S7, W, X) to addresses");
    for (const auto& entry : node) {
      const auto name = entry.first.Scalar();
      const auto bank = banks::parse_bank_name(name);
      if (!bank) yaml_.fail(entry.first, fmt::format("unknown bank '{}' (banks are A, B, C, D1..D4, S1..S7, W, X)", name));
      config_.bank_bases[index_of(*bank)] = static_cast<std::uint16_t>(yaml_.number(entry.second, 0, 0xFFFF));
      config_.bank_origins[index_of(*bank)] = yaml_.position(entry.second);
    }
  }

  void devices(const YAML::Node& node) {
    if (!node.IsMap()) yaml_.fail(node, "devices must map D1..D4 to { type, address }");
    for (const auto& entry : node) {
      const auto name = entry.first.Scalar();
      const auto bank = banks::parse_bank_name(name);
      if (!bank || !banks::is_device_bank(*bank))
        yaml_.fail(entry.first, fmt::format("unknown device bank '{}' (device banks are D1, D2, D3, D4)", name));
      const auto& dev = entry.second;
      yaml_.expect_keys(dev, fmt::format("devices.{}", name), {"type", "address"});
      if (!dev["type"]) yaml_.fail(dev, fmt::format("devices.{} needs a type", name));
      if (!dev["address"]) yaml_.fail(dev, fmt::format("devices.{} needs the device's UnimaBUS address", name));
      DeviceConfig device;
      const auto type = yaml_.text(dev["type"]);
      device.table = banks::find_device_type(type);
      if (!device.table)
        yaml_.fail(dev["type"], fmt::format("unknown device type '{}' (known: {})", type,
                                            fmt::join(banks::device_type_ids(), ", ")));
      device.address = static_cast<std::uint8_t>(yaml_.number(dev["address"], 0, 255));
      // A D_N is identified by its type and address (SPEC §6): a unit's CHP controller, USC
      // and UVR share its address, but two of one type there could not be told apart.
      for (unsigned n = 1; n <= 4; ++n) {
        const auto& other = config_.devices[n - 1];
        if (other && other->table == device.table && other->address == device.address)
          yaml_.fail(dev, fmt::format("devices.{} and devices.D{} are both a {} at UnimaBUS address {}: a D_N is "
                                      "identified by its type and address, so telegrams could not tell them apart",
                                      name, n, device.table->id, device.address));
      }
      config_.devices[banks::bank_number(*bank) - 1] = device;
    }
  }

  banks::SourceRef source(const YAML::Node& node, SourceUse use) const {
    auto parsed = parse_source_ref(yaml_.text(node), shapes_, use);
    if (auto* error = std::get_if<std::string>(&parsed)) yaml_.fail(node, *error);
    return std::get<banks::SourceRef>(std::move(parsed));
  }

  void mapping_list(const YAML::Node& node, std::string_view what, SourceUse use,
                    std::array<std::optional<banks::SourceRef>, banks::Mapping::entries>& entries) const {
    if (!node.IsSequence()) yaml_.fail(node, fmt::format("mapping.{} must be a list of sources", what));
    if (node.size() > entries.size())
      yaml_.fail(node, fmt::format("mapping.{} has {} entries; there are {}", what, node.size(), entries.size()));
    for (std::size_t n = 0; n < node.size(); ++n)
      if (!node[n].IsNull()) entries[n] = source(node[n], use);  // ~ leaves an entry unmapped
  }

  // Bank A's entries: a source, converted to tenths of its unit, or `{ source: …, raw: true }`
  // copied unchanged (SPEC §1).
  void analog_mapping(const YAML::Node& node, banks::Mapping& m) const {
    if (!node.IsSequence()) yaml_.fail(node, "mapping.A must be a list of sources");
    if (node.size() > m.analog.size())
      yaml_.fail(node, fmt::format("mapping.A has {} entries; there are {}", node.size(), m.analog.size()));
    for (std::size_t n = 0; n < node.size(); ++n) {
      const auto& entry = node[n];
      if (entry.IsNull()) continue;  // ~ leaves an entry unmapped
      if (!entry.IsMap()) {
        m.analog[n] = source(entry, SourceUse::analog);
        continue;
      }
      yaml_.expect_keys(entry, fmt::format("mapping.A entry {}", n), {"source", "raw"});
      if (!entry["source"]) yaml_.fail(entry, "a mapping.A entry written as a map needs a source, e.g. { source: D1+0x02, raw: true }");
      m.analog[n] = source(entry["source"], SourceUse::analog);
      if (entry["raw"]) m.analog_raw[n] = yaml_.boolean(entry["raw"]);
    }
  }

  void mapping(const YAML::Node& node) {
    yaml_.expect_keys(node, "mapping", {"A", "B", "user_inputs", "user_outputs"});
    auto& m = config_.mapping;
    if (node["A"]) analog_mapping(node["A"], m);
    if (node["B"]) mapping_list(node["B"], "B", SourceUse::bit, m.bits);
    if (node["user_inputs"]) mapping_list(node["user_inputs"], "user_inputs", SourceUse::bit, m.user_inputs);
    if (node["user_outputs"]) mapping_list(node["user_outputs"], "user_outputs", SourceUse::bit, m.user_outputs);
  }

  void blocks(const YAML::Node& node) {
    if (!node.IsSequence()) yaml_.fail(node, "blocks must be a list");
    std::array<const YAML::Node*, banks::c_bank::user_output_count + 1> output_users{};
    std::vector<YAML::Node> kept;  // output_users points into these
    kept.reserve(node.size());
    for (const auto& item : node) {
      kept.push_back(item);
      const auto& b = kept.back();
      if (!b.IsMap() || !b["type"]) yaml_.fail(b, "a block needs a type: read, write, capture, poll or send");
      const auto type = yaml_.choice(b["type"], {"read", "write", "capture", "poll", "send"});
      Block block;
      block.origin = yaml_.position(b);
      if (type == "read") {
        block.type = Block::Type::read;
        yaml_.expect_keys(b, "a read block", {"type", "register", "source"});
      } else if (type == "write") {
        block.type = Block::Type::write;
        yaml_.expect_keys(b, "a write block", {"type", "register", "output"});
      } else if (type == "capture") {
        block.type = Block::Type::capture;
        yaml_.expect_keys(b, "a capture block", {"type", "device", "register", "output"});
      } else if (type == "poll") {
        block.type = Block::Type::poll;
        yaml_.expect_keys(b, "a poll block", {"type", "device", "register", "period", "output", "function", "data_type",
                                              "count", "word_order", "scale", "profile", "point", "operand"});
      } else {
        block.type = Block::Type::send;
        yaml_.expect_keys(b, "a send block", {"type", "device", "register", "period", "source", "function", "data_type",
                                              "word_order", "scale", "profile", "point", "operand"});
      }
      const auto required = [&](const char* key) {
        if (!b[key]) yaml_.fail(b, fmt::format("a {} block needs '{}'", type, key));
        return b[key];
      };
      if (block.is_slave_block() || (!b["point"] && !b["operand"]))
        block.reg = static_cast<std::uint16_t>(yaml_.number(required("register"), 0, 0xFFFF));
      if (block.type == Block::Type::read) block.source = source(required("source"), SourceUse::analog);
      if (block.type == Block::Type::send) (void)required("source");  // parsed with its function, below
      if (block.type == Block::Type::write || block.type == Block::Type::capture || block.type == Block::Type::poll) {
        const auto& out = required("output");
        block.output = static_cast<unsigned>(yaml_.number(out, 1, banks::c_bank::user_output_count));
        if (const auto* other = output_users[block.output])
          yaml_.fail(out, fmt::format("user analog output {} is already the output of the block at {}", block.output,
                                      yaml_.position(*other)));
        output_users[block.output] = &b;
      }
      if (block.type == Block::Type::capture || block.type == Block::Type::poll || block.type == Block::Type::send) {
        const auto& device = required("device");
        block.device = static_cast<std::uint8_t>(yaml_.number(device, 1, 247));
        if (block.type == Block::Type::capture && block.device == config_.modbus.address)
          yaml_.fail(device, fmt::format("a capture block listens to another device; {} is the bridge's own "
                                         "Modbus address (modbus.address)", block.device));
      }
      if (block.type == Block::Type::poll || block.type == Block::Type::send) {
        const auto& period = required("period");
        block.period = yaml_.duration(period);
        if (block.period.count() == 0) yaml_.fail(period, "the period must be longer than 0");
        master_point(b, block);
      }
      config_.blocks.push_back(std::move(block));
    }
  }

  // What a poll or send block reads or writes on the foreign slave: a profile point, or a
  // register with function, data type, word order and scale (SPEC §4 extensions).
  void master_point(const YAML::Node& b, Block& block) {
    const bool poll = block.type == Block::Type::poll;
    const auto device = config_.modbus.master.devices.find(block.device);
    const auto* device_profile = device != config_.modbus.master.devices.end() ? device->second.profile : nullptr;
    block.profile = b["profile"] ? profile(b["profile"]) : device_profile;
    if (!block.profile) block.profile = profile_of_device_[block.device].first;  // named by an earlier block
    if (b["profile"] && device_profile && block.profile != device_profile)
      yaml_.fail(b["profile"], fmt::format("device {} is a {} (modbus.master.devices.{})", block.device,
                                           device_profile->id, block.device));
    const auto& seen = profile_of_device_[block.device];
    if (block.profile && seen.first && seen.first != block.profile)
      yaml_.fail(b["profile"] ? b["profile"] : b,
                 fmt::format("device {} is a {} in the block at {}", block.device, seen.first->id, seen.second));
    if (block.profile && !seen.first) profile_of_device_[block.device] = {block.profile, block.origin};

    if (b["scale"]) {
      block.scale = yaml_.decimal(b["scale"]);
      if (block.scale == 0) yaml_.fail(b["scale"], "scale must be a number other than 0");
    }
    if (b["point"] && b["operand"]) yaml_.fail(b["operand"], "a block names a 'point' or an 'operand', not both");
    if (b["point"]) point_block(b, block, poll);
    else if (b["operand"]) operand_block(b, block, poll);
    else register_block(b, block, poll);
    if (!poll) send_source(b["source"], block);
  }

  // A coil (function 5) takes a bit source, or a whole register (on when not 0).
  void send_source(const YAML::Node& node, Block& block) const {
    if (block.function == 5) {
      auto parsed = parse_source_ref(yaml_.text(node), shapes_, SourceUse::bit);
      if (auto* ref = std::get_if<banks::SourceRef>(&parsed)) {
        block.source = std::move(*ref);
        return;
      }
    }
    block.source = source(node, SourceUse::analog);
  }

  void point_block(const YAML::Node& b, Block& block, bool poll) {
    const auto& point_node = b["point"];
    if (!block.profile)
      yaml_.fail(point_node, fmt::format("a point needs a device profile: set 'profile' here, or "
                                         "modbus.master.devices.{}.profile", block.device));
    for (const char* key : {"register", "data_type", "count", "word_order"})
      if (b[key]) yaml_.fail(b[key], fmt::format("'{}' comes from the profile's point; leave it out", key));
    block.point = yaml_.text(point_node);
    const auto* point = block.profile->find(block.point);
    if (!point)
      yaml_.fail(point_node, fmt::format("profile {} has no point '{}' (`unima-bridge profiles {}` lists them)",
                                         block.profile->id, block.point, block.profile->id));
    if (point->length > 1)
      yaml_.fail(point_node, fmt::format("{} is an area of {} registers from {}; name one of them with 'register' "
                                         "(and 'data_type') instead of 'point'", point->name, point->length, point->reg));
    const auto& functions = poll ? point->read_functions : point->write_functions;
    if (functions.empty())
      yaml_.fail(point_node, fmt::format("{} cannot be {} (the device {} it only)", point->name,
                                         poll ? "read" : "written", poll ? "writes" : "reads"));
    block.function = functions.front();
    if (b["function"]) {
      block.function = static_cast<std::uint8_t>(yaml_.number(b["function"], 1, 127));
      if (std::find(functions.begin(), functions.end(), block.function) == functions.end())
        yaml_.fail(b["function"], fmt::format("{} is {} with function {}, not {}", point->name, poll ? "read" : "written",
                                              fmt::join(functions, " or "), block.function));
    }
    block.reg = point->reg;
    block.data_type = point->type;
    block.count = point->type == master::ValueType::bits ? point->count : 1;
    block.word_order = block.profile->word_order;
    if (!b["scale"]) block.scale = point->scale;
    if (b["scale"] && point->type == master::ValueType::bits) yaml_.fail(b["scale"], "bits are not scaled");
  }

  // A PLC operand (`D200`, `X17`) of the profile's classes: its address and functions come
  // from the class (master/plc_operand); data_type, word_order and function as for a register.
  void operand_block(const YAML::Node& b, Block& block, bool poll) {
    const auto& node = b["operand"];
    if (!block.profile || block.profile->operands.empty())
      yaml_.fail(node, fmt::format("an operand needs the profile of a PLC named by operands (e.g. 'profile: "
                                   "wecon-lx5v'){}", block.profile ? fmt::format("; {} has points", block.profile->id) : ""));
    if (b["register"]) yaml_.fail(b["register"], "'register' comes from the operand; leave it out");
    auto resolved = master::resolve_operand(*block.profile, yaml_.text(node));
    if (const auto* error = std::get_if<std::string>(&resolved)) yaml_.fail(node, *error);
    const auto& operand = std::get<master::ResolvedOperand>(resolved);
    const auto& functions = poll ? operand.operand_class->read_functions : operand.operand_class->write_functions;
    if (functions.empty())
      yaml_.fail(node, fmt::format("{} cannot be written: the PLC's {} are read only ({})", yaml_.text(node),
                                   operand.operand_class->name, operand.operand_class->label));
    block.point = operand.operand_class->format(operand.number);
    block.reg = operand.reg;
    register_block(b, block, poll, &functions);
  }

  // `allowed`: the functions an operand's class takes, the first the default; else the
  // seed's (MBS_F04 reads with function 4, MBS_F06 writes with 6) and the extensions.
  void register_block(const YAML::Node& b, Block& block, bool poll,
                      const std::vector<std::uint8_t>* allowed = nullptr) {
    using master::ValueType;
    block.function = allowed ? allowed->front() : poll ? 4 : 6;
    if (const auto fn = b["function"]) {
      block.function = static_cast<std::uint8_t>(std::stoul(poll ? yaml_.choice(fn, {"1", "2", "3", "4"})
                                                                 : yaml_.choice(fn, {"5", "6", "16"})));
      if (allowed && std::find(allowed->begin(), allowed->end(), block.function) == allowed->end())
        yaml_.fail(fn, fmt::format("{} is {} with function {}, not {}", block.point, poll ? "read" : "written",
                                   fmt::join(*allowed, " or "), block.function));
    } else if (allowed && !poll && block.function == 6 && b["data_type"]) {
      // A 32-bit value goes with function 16 where the class has it.
      const auto type = master::parse_value_type(yaml_.text(b["data_type"]));
      if (type && master::register_span(*type) == 2 &&
          std::find(allowed->begin(), allowed->end(), std::uint8_t{16}) != allowed->end())
        block.function = 16;
    }
    if (block.profile && !block.profile->implements(block.function))
      yaml_.fail(b["function"] ? b["function"] : b,
                 fmt::format("{} does not implement function {} (it implements {}){}", block.profile->id,
                             block.function, fmt::join(block.profile->functions, ", "),
                             b["function"] ? "" : "; set 'function'"));
    const bool bits = block.function == 1 || block.function == 2 || block.function == 5;
    block.data_type = bits ? ValueType::bits : ValueType::word;
    if (const auto type_node = b["data_type"]) {
      const auto name = yaml_.text(type_node);
      const auto type = master::parse_value_type(name);
      if (!type) yaml_.fail(type_node, fmt::format("'{}' is not one of: bits, word, int, dint, dword, real", name));
      const bool fits = bits ? *type == ValueType::bits
                             : *type != ValueType::bits && (block.function != 6 || master::register_span(*type) == 1);
      if (!fits)
        yaml_.fail(type_node, fmt::format("function {} does not {} {}{}", block.function, poll ? "read" : "write", name,
                                          block.function == 6 ? " (function 6 writes one register: word or int)" : ""));
      block.data_type = *type;
    }
    if (const auto count = b["count"]) {
      if (!bits) yaml_.fail(count, "'count' is for bits (functions 1 and 2): how many are read into the output");
      block.count = static_cast<std::uint16_t>(yaml_.number(count, 1, 16));
    }
    block.word_order = block.profile ? block.profile->word_order : master::WordOrder::low_first;
    if (const auto order_node = b["word_order"]) {
      const auto order = master::parse_word_order(yaml_.text(order_node));
      if (!order) yaml_.fail(order_node, fmt::format("'{}' is not one of: low_first, high_first", yaml_.text(order_node)));
      if (master::register_span(block.data_type) != 2)
        yaml_.fail(order_node, "word_order is for the 32-bit types (dint, dword, real)");
      block.word_order = *order;
    }
    if (b["scale"] && bits) yaml_.fail(b["scale"], "bits are not scaled");
    if (std::uint32_t{block.reg} + block.extent() > 0x10000)
      yaml_.fail(b["register"] ? b["register"] : b, "the value runs past register 0xFFFF");
  }

  void log(const YAML::Node& node) {
    yaml_.expect_keys(node, "log", {"level"});
    if (node["level"])
      config_.log.level = yaml_.choice(node["level"], {"trace", "debug", "info", "warn", "error", "critical", "off"});
  }

  void monitor(const YAML::Node& node) {
    yaml_.expect_keys(node, "monitor",
                      {"file", "stdout", "format", "max_size", "max_files", "queue", "filter", "indicators"});
    auto& m = config_.monitor;
    if (node["file"]) {
      m.file = yaml_.text(node["file"]);
      if (m.file.empty()) yaml_.fail(node["file"], "monitor.file must name a file");
      check_log_path(node["file"], "monitor.file", m.file);
    }
    if (node["stdout"]) m.to_stdout = yaml_.boolean(node["stdout"]);
    if (node["format"]) m.format = yaml_.choice(node["format"], {"text", "json"}) == "json" ? monitor::MonitorFormat::json : monitor::MonitorFormat::text;
    if (node["max_size"]) m.max_size = yaml_.byte_size(node["max_size"], 4096, 1ull << 40);
    if (node["max_files"]) m.max_files = static_cast<unsigned>(yaml_.number(node["max_files"], 1, 100));
    if (node["queue"]) m.queue = static_cast<unsigned>(yaml_.number(node["queue"], 16, 1'000'000));
    if (const auto filter = node["filter"]) {
      yaml_.expect_keys(filter, "monitor.filter", {"address", "function", "from", "to"});
      using monitor::FilterField;
      for (const auto& [key, field] : {std::pair{"address", FilterField::address}, std::pair{"function", FilterField::function},
                                       std::pair{"from", FilterField::from}, std::pair{"to", FilterField::to}}) {
        const auto value = filter[key];
        if (!value) continue;
        try {
          monitor::set_filter_field(m.filter, field, yaml_.text(value));
        } catch (const monitor::FilterSyntaxError& e) {
          yaml_.fail(value, fmt::format("monitor.filter: {}", e.what()));
        }
      }
      try {
        monitor::check_filter_range(m.filter);
      } catch (const monitor::FilterSyntaxError& e) {
        yaml_.fail(filter["to"] ? filter["to"] : filter["from"], fmt::format("monitor.filter: {}", e.what()));
      }
    }
    if (const auto indicators = node["indicators"]) {
      if (!indicators.IsSequence()) yaml_.fail(indicators, "indicators must be a list of { address, register }");
      for (const auto& entry : indicators) {
        if (m.indicators.size() == 4) yaml_.fail(entry, "at most 4 capture indicators (seed 004 §8)");
        yaml_.expect_keys(entry, "an indicator", {"address", "register"});
        if (!entry["address"] || !entry["register"]) yaml_.fail(entry, "an indicator needs an address and a register");
        m.indicators.push_back({static_cast<std::uint8_t>(yaml_.number(entry["address"], 0, 255)),
                                static_cast<std::uint16_t>(yaml_.number(entry["register"], 0, 0xFFFF))});
      }
    }
  }

  // Also without the section: the default path is where the daemon listens then.
  void status(const YAML::Node& node, const YAML::Node& root) {
    auto& socket = config_.status.socket;
    if (node) yaml_.expect_keys(node, "status", {"socket"});
    if (!node || !node["socket"]) return check_socket_path(node ? node : root, "status.socket", socket);
    socket = yaml_.text(node["socket"]);
    if (const auto error = socket_path_error(socket)) yaml_.fail(node["socket"], fmt::format("status.socket {}", *error));
    check_socket_path(node["socket"], "status.socket", socket);
  }

  static constexpr std::array<std::string_view, 7> tcp_keys = {"listen",        "port",  "max_clients", "idle_timeout",
                                                              "frame_timeout", "allow", "read_only"};

  // The keys modbus.tcp and modbus.tls share; `key` names the section in messages.
  TcpSlaveConfig tcp_slave(const YAML::Node& node, std::string_view key, TcpSlaveConfig t) {
    if (node["listen"]) {
      t.listen = yaml_.text(node["listen"]);
      if (const auto error = listen_address_error(t.listen, HostRule::listen_address)) yaml_.fail(node["listen"], *error);
    }
    if (node["port"]) t.port = static_cast<std::uint16_t>(yaml_.number(node["port"], 0, 65535));
    if (node["max_clients"]) t.max_clients = static_cast<unsigned>(yaml_.number(node["max_clients"], 1, 10000));
    if (node["idle_timeout"]) t.idle_timeout = yaml_.duration(node["idle_timeout"]);
    if (node["frame_timeout"]) {
      t.frame_timeout = yaml_.duration(node["frame_timeout"]);
      if (t.frame_timeout.count() <= 0) yaml_.fail(node["frame_timeout"], fmt::format("{}.frame_timeout must be above 0", key));
    }
    if (node["allow"]) t.allow = allow_list(node["allow"], fmt::format("{}.allow", key));
    if (node["read_only"]) t.read_only = yaml_.boolean(node["read_only"]);
    return t;
  }

  TlsSlaveConfig tls_slave(const YAML::Node& node) {
    std::vector<std::string_view> keys(tcp_keys.begin(), tcp_keys.end());
    for (const char* k : {"certificate", "key", "ca", "roles"}) keys.push_back(k);
    yaml_.expect_keys(node, "modbus.tls", keys);
    TlsSlaveConfig tls;
    tls.origin = yaml_.position(node);
    tls.connection = tcp_slave(node, "modbus.tls", TlsSlaveConfig::default_connection());
    for (const auto& [key, file] : {std::pair{"certificate", &tls.certificate}, std::pair{"key", &tls.key},
                                    std::pair{"ca", &tls.ca}}) {
      if (!node[key]) yaml_.fail(node, fmt::format("modbus.tls needs '{}', a PEM file", key));
      *file = yaml_.text(node[key]);
      if (file->empty()) yaml_.fail(node[key], fmt::format("modbus.tls.{} must be the path of a PEM file", key));
    }
    if (const auto roles = node["roles"]) {
      if (!roles.IsMap()) yaml_.fail(roles, "modbus.tls.roles must map each role to { write: [...] }");
      for (const auto& role : roles) pending_roles_.emplace_back(yaml_.text(role.first), role.second);
    }
    return tls;
  }

  // A role's `write: [W, X, 0x0201]`: banks by name, registers by address, resolved once
  // the register map is known (after validate_layout).
  void resolve_roles() {
    if (!config_.modbus.tls) return;
    const auto map = address_map(config_);
    for (const auto& [name, node] : pending_roles_) {
      if (!node.IsMap()) yaml_.fail(node, fmt::format("modbus.tls.roles.{} must be {{ write: [...] }}", name));
      yaml_.expect_keys(node, fmt::format("modbus.tls.roles.{}", name), {"write"});
      auto rights = modbus::WriteRights::nothing();
      if (const auto write = node["write"]) {
        if (!write.IsSequence())
          yaml_.fail(write, fmt::format("modbus.tls.roles.{}.write must be a list of banks and registers, e.g. [W, X, 0x0201]", name));
        for (const auto& item : write) {
          const auto text = yaml_.text(item);
          if (const auto bank = banks::parse_bank_name(text)) {
            const auto window = std::find_if(map.windows().begin(), map.windows().end(), [&](const banks::Window& w) {
              return w.kind == banks::Window::Kind::bank && w.bank == *bank;
            });
            if (window == map.windows().end())
              yaml_.fail(item, fmt::format("bank {} is not served by this config", text));
            rights.allow(window->first, static_cast<std::uint16_t>(window->end() - 1));
          } else {
            const auto address = static_cast<std::uint16_t>(yaml_.number(item, 0, 0xFFFF));
            if (!map.find(address)) yaml_.fail(item, fmt::format("register {:#06x} is in no bank or block of this config", address));
            rights.allow(address, address);
          }
        }
      }
      config_.modbus.tls->roles.insert_or_assign(name, std::move(rights));
    }
  }

  PeerAllowList allow_list(const YAML::Node& node, std::string_view key) {
    if (!node.IsSequence() || node.size() == 0)
      yaml_.fail(node, fmt::format("{} must be a list of addresses and CIDR ranges, e.g. [192.168.10.0/24, 127.0.0.1]", key));
    PeerAllowList list;
    for (const auto& item : node) {
      auto parsed = parse_network_range(yaml_.text(item));
      if (auto* error = std::get_if<std::string>(&parsed)) yaml_.fail(item, fmt::format("{}: {}", key, *error));
      list.ranges.push_back(std::get<NetworkRange>(std::move(parsed)));
    }
    return list;
  }

  void http(const YAML::Node& node) {
    yaml_.expect_keys(node, "http", {"listen", "port", "max_clients", "tls", "users"});
    HttpConfig h;
    h.origin = yaml_.position(node);
    if (node["listen"]) {
      h.listen = yaml_.text(node["listen"]);
      if (const auto error = listen_address_error(h.listen, HostRule::listen_address)) yaml_.fail(node["listen"], *error);
    }
    if (node["port"]) h.port = static_cast<std::uint16_t>(yaml_.number(node["port"], 0, 65535));
    if (node["max_clients"]) h.max_clients = static_cast<unsigned>(yaml_.number(node["max_clients"], 1, 1000));
    if (const auto tls = node["tls"]) {
      yaml_.expect_keys(tls, "http.tls", {"certificate", "key"});
      HttpTlsConfig t;
      for (const auto& [key, file] : {std::pair{"certificate", &t.certificate}, std::pair{"key", &t.key}}) {
        if (!tls[key]) yaml_.fail(tls, fmt::format("http.tls needs '{}', a PEM file", key));
        *file = yaml_.text(tls[key]);
        if (file->empty()) yaml_.fail(tls[key], fmt::format("http.tls.{} must be the path of a PEM file", key));
      }
      h.tls = t;
    }
    if (const auto users = node["users"]) {
      h.users = yaml_.text(users);
      if (h.users.empty()) yaml_.fail(users, "http.users must be the path of a file of name:password-hash lines");
    }
    config_.http = h;
  }

  void mqtt(const YAML::Node& node) {
    yaml_.expect_keys(node, "mqtt", {"broker", "client_id", "topic", "username", "password_file", "ca", "certificate",
                                     "key", "version", "publish", "commands"});
    MqttConfig m;
    m.origin = yaml_.position(node);
    if (!node["broker"]) yaml_.fail(node, "mqtt needs 'broker', e.g. mqtt://127.0.0.1:1883 or mqtts://broker.example:8883");
    m.broker = yaml_.text(node["broker"]);
    std::string_view rest = m.broker;
    if (rest.starts_with("mqtts://")) {
      m.tls = true;
      rest.remove_prefix(8);
    } else if (rest.starts_with("mqtt://")) {
      rest.remove_prefix(7);
    } else {
      yaml_.fail(node["broker"], fmt::format("mqtt.broker '{}' must start with mqtt:// or mqtts://", m.broker));
    }
    if (rest.ends_with('/')) rest.remove_suffix(1);
    // A port is optional: the protocol's own (1883, 8883) when none is written.
    const bool has_port = rest.starts_with('[') ? rest.find("]:") != std::string_view::npos
                                                : std::count(rest.begin(), rest.end(), ':') == 1;
    const std::string with_port = has_port ? std::string(rest) : fmt::format("{}:{}", rest, m.tls ? 8883 : 1883);
    auto endpoint = parse_host_port(with_port, HostRule::address_or_name, PortRule::nonzero);
    if (auto* error = std::get_if<std::string>(&endpoint)) yaml_.fail(node["broker"], fmt::format("mqtt.broker: {}", *error));
    m.endpoint = std::get<HostPort>(endpoint);
    m.client_id = node["client_id"] ? yaml_.text(node["client_id"]) : default_client_id();
    if (m.client_id.empty() || m.client_id.size() > 64)
      yaml_.fail(node["client_id"] ? node["client_id"] : node, "mqtt.client_id must be 1..64 characters");
    m.topic = node["topic"] ? yaml_.text(node["topic"]) : "unima/" + m.client_id;
    if (m.topic.empty() || m.topic.back() == '/' || m.topic.find_first_of("#+") != std::string::npos)
      yaml_.fail(node["topic"] ? node["topic"] : node, "mqtt.topic must be a topic prefix without wildcards (# +) or a trailing /");
    if (node["username"]) m.username = yaml_.text(node["username"]);
    if (node["password_file"]) m.password_file = yaml_.text(node["password_file"]);
    if (!m.password_file.empty() && m.username.empty())
      yaml_.fail(node["password_file"], "mqtt.password_file needs mqtt.username");
    for (const auto& [key, file] : {std::pair{"ca", &m.ca}, std::pair{"certificate", &m.certificate}, std::pair{"key", &m.key}}) {
      if (!node[key]) continue;
      if (!m.tls) yaml_.fail(node[key], fmt::format("mqtt.{} is for mqtts:// brokers", key));
      *file = yaml_.text(node[key]);
    }
    if (m.certificate.empty() != m.key.empty())
      yaml_.fail(node, "mqtt.certificate and mqtt.key go together (the client's certificate and its key)");
    if (node["version"]) {
      const auto version = yaml_.text(node["version"]);
      if (version == "3.1.1") m.version = 4;
      else if (version == "5") m.version = 5;
      else yaml_.fail(node["version"], "mqtt.version must be 3.1.1 or 5");
    }
    if (const auto publish = node["publish"]) {
      yaml_.expect_keys(publish, "mqtt.publish", {"period", "on_change"});
      if (publish["period"]) {
        m.period = yaml_.duration(publish["period"]);
        if (m.period < std::chrono::seconds(1)) yaml_.fail(publish["period"], "mqtt.publish.period must be 1s or more");
      }
      if (publish["on_change"]) m.on_change = yaml_.boolean(publish["on_change"]);
    }
    if (node["commands"]) m.commands = yaml_.boolean(node["commands"]);
    config_.mqtt = m;
  }

  static std::string default_client_id() {
    char host[256] = {};
    if (::gethostname(host, sizeof host - 1) != 0 || host[0] == '\0') return "unima-bridge";
    return std::string("unima-bridge-") + host;
  }

  void state(const YAML::Node& node) {
    config_.state.file = default_state_file(config_.file);
    if (!node) return;
    yaml_.expect_keys(node, "state", {"file"});
    if (!node["file"]) return;
    const auto file = yaml_.text(node["file"]);
    if (file.empty()) yaml_.fail(node["file"], "state.file must be a path, or none to keep no state");
    config_.state.file = file == "none" ? std::string() : file;
  }

  void validate_layout(const YAML::Node& root) {
    try {
      (void)address_map(config_);
    } catch (const banks::OverlapError& e) {
      const std::string message = e.what();
      // The windows the file set carry their position; when none did, point at the file.
      if (message.starts_with(config_.file + ":")) throw ConfigError(message);
      throw ConfigError(fmt::format("{}: {}", yaml_.position(root), message));
    }
  }

  YamlReader yaml_;
  Config config_;
  std::vector<std::pair<std::string, YAML::Node>> pending_roles_;
  banks::BankShapes shapes_{};
  std::map<std::uint8_t, std::pair<const master::DeviceProfile*, std::string>> profile_of_device_;
};

}  // namespace

Config load_text(const std::string& text, const std::string& origin) {
  return banks::read_yaml_document<ConfigError>(text, origin,
                                                [&](const YAML::Node& root) { return Loader(origin).load(root); });
}

Config load_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ConfigError(fmt::format("{}: cannot open the config file: {}", path, std::strerror(errno)));
  std::ostringstream text;
  text << in.rdbuf();
  return load_text(text.str(), path);
}

modbus::RtuTiming line_timing(const RtuConfig& line) {
  return modbus::rtu_timing(line.baud, line.parity != Parity::none, line.stop_bits);
}

banks::BankShapes bank_shapes(const Config& config) {
  std::array<const banks::DeviceTable*, 4> tables{};
  for (std::size_t i = 0; i < 4; ++i)
    if (config.devices[i]) tables[i] = config.devices[i]->table;
  return banks::standard_shapes(tables, banks::io_module_table(), banks::bridge_internal_table());
}

banks::AddressMap address_map(const Config& config) {
  const auto shapes = bank_shapes(config);
  std::vector<banks::Window> windows;
  for (BankId bank : banks::all_banks) {
    const auto length = shapes[index_of(bank)].length;
    if (length == 0) continue;
    banks::Window w;
    w.kind = banks::Window::Kind::bank;
    w.bank = bank;
    w.first = config.bank_bases[index_of(bank)];
    w.count = length;
    w.name = fmt::format("bank {}", banks::bank_name(bank));
    w.origin = config.bank_origins[index_of(bank)];
    windows.push_back(std::move(w));
  }
  for (const Block* block : config.active_blocks()) {
    if (block->type != Block::Type::read && block->type != Block::Type::write) continue;
    banks::Window w;
    w.kind = block->type == Block::Type::read ? banks::Window::Kind::read_block : banks::Window::Kind::write_block;
    w.first = block->reg;
    w.count = 1;
    if (block->source) w.source = *block->source;
    w.output = static_cast<std::uint8_t>(block->output);
    w.name = fmt::format("{} block 0x{:04X}", block_type_name(block->type), block->reg);
    w.origin = block->origin;
    windows.push_back(std::move(w));
  }
  return banks::AddressMap(std::move(windows));
}

std::string_view block_type_name(Block::Type type) {
  switch (type) {
    case Block::Type::read: return "read";
    case Block::Type::write: return "write";
    case Block::Type::capture: return "capture";
    case Block::Type::poll: return "poll";
    case Block::Type::send: return "send";
  }
  return "?";
}

std::uint16_t Block::extent() const {
  if (data_type == master::ValueType::bits) return count;
  return static_cast<std::uint16_t>(master::register_span(data_type));
}

std::vector<const Block*> Config::active_blocks() const {
  std::vector<const Block*> active;
  for (const auto& block : blocks)
    if (block.is_slave_block() == (modbus.mode == ModbusMode::slave)) active.push_back(&block);
  return active;
}

std::vector<std::string> warnings(const Config& config) {
  std::vector<std::string> found;
  const bool slave = config.modbus.mode == ModbusMode::slave;
  if (slave && !config.modbus.master.origin.empty())
    found.push_back(fmt::format("{}: modbus.master is set, but this bridge is a slave; the master settings are unused",
                                config.modbus.master.origin));
  for (const auto& block : config.blocks) {
    if (block.is_slave_block() != slave)
      found.push_back(fmt::format("{}: {} block ignored: {} blocks act in {} mode only, this bridge is a {}",
                                  block.origin, block_type_name(block.type), block_type_name(block.type),
                                  block.is_slave_block() ? "slave" : "master", slave ? "slave" : "master"));
    else if (block.type == Block::Type::capture && !config.modbus.rtu)
      found.push_back(fmt::format("{}: capture block inactive: capture listens on a Modbus RTU line, and "
                                  "modbus.rtu is not set", block.origin));
  }
  if (const auto& http = config.http; http && !is_loopback_address(http->listen)) {
    if (http->users.empty())
      found.push_back(fmt::format("{}: http listens on {} without http.users: anyone who reaches the port reads the plant's "
                                  "values and the monitor", http->origin, http->listen));
    else if (!http->tls)
      found.push_back(fmt::format("{}: http listens on {} without http.tls: passwords cross the network in clear",
                                  http->origin, http->listen));
  }
  if (!slave) {
    const auto more = foreign_slave_warnings(config);
    found.insert(found.end(), more.begin(), more.end());
  }
  return found;
}

}  // namespace unima::config
