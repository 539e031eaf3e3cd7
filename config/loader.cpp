#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>

#include <fmt/format.h>

#include "banks/table_catalog.hpp"
#include "config/config.hpp"
#include "config/source_ref_parser.hpp"
#include "config/yaml_reader.hpp"

namespace unima::config {

namespace {

using banks::BankId;

class Loader {
 public:
  explicit Loader(const std::string& origin) : yaml_(origin) { config_.file = origin; }

  Config load(const YAML::Node& root) {
    if (!root.IsNull() && !root.IsMap()) yaml_.fail(root, "the config must be a mapping of sections");
    yaml_.expect_keys(root, "the config",
                      {"unimabus", "modbus", "banks", "devices", "mapping", "blocks", "log", "monitor", "status"});
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
    if (root["status"]) status(root["status"]);
    validate_layout(root);
    return std::move(config_);
  }

 private:
  void unimabus(const YAML::Node& node) {
    yaml_.expect_keys(node, "unimabus", {"address", "transport", "listen", "offline_after", "sim"});
    auto& u = config_.unimabus;
    if (node["address"]) u.address = static_cast<std::uint8_t>(yaml_.number(node["address"], 0, 255));
    if (node["transport"]) {
      const auto t = yaml_.choice(node["transport"], {"sim", "feed", "replay"});
      if (t == "replay") yaml_.fail(node["transport"], "the replay transport is not available in this version");
      u.transport = t == "feed" ? TransportKind::feed : TransportKind::sim;
    }
    if (node["listen"]) u.listen = yaml_.text(node["listen"]);
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

  void check_listen(const YAML::Node& node) const {
    const auto& s = config_.unimabus.listen;
    if (s.starts_with("unix:")) {
      if (s.size() <= 5) yaml_.fail(node, "unix: needs a socket path, e.g. unix:/run/unima-bridge/feed.sock");
      return;
    }
    const auto colon = s.rfind(':');
    if (colon == std::string::npos || colon == 0 || colon + 1 == s.size())
      yaml_.fail(node, fmt::format("'{}' is not host:port or unix:/path", s));
    const auto port = s.substr(colon + 1);
    if (port.find_first_not_of("0123456789") != std::string::npos || port.size() > 5 || std::stoul(port) > 65535)
      yaml_.fail(node, fmt::format("'{}' has no valid port", s));
  }

  void modbus(const YAML::Node& node) {
    yaml_.expect_keys(node, "modbus", {"mode", "address", "tcp", "rtu", "readable_write_banks", "extensions"});
    auto& m = config_.modbus;
    if (node["mode"]) {
      const auto mode = yaml_.choice(node["mode"], {"slave", "master"});
      if (mode == "master") yaml_.fail(node["mode"], "master mode is not available in this version");
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
      yaml_.expect_keys(tcp, "modbus.tcp", {"listen", "port", "max_clients", "idle_timeout"});
      TcpSlaveConfig t;
      if (tcp["listen"]) t.listen = yaml_.text(tcp["listen"]);
      if (tcp["port"]) t.port = static_cast<std::uint16_t>(yaml_.number(tcp["port"], 0, 65535));
      if (tcp["max_clients"]) t.max_clients = static_cast<unsigned>(yaml_.number(tcp["max_clients"], 1, 10000));
      if (tcp["idle_timeout"]) t.idle_timeout = yaml_.duration(tcp["idle_timeout"]);
      m.tcp = t;
    }
    if (const auto rtu = node["rtu"]) m.rtu = rtu_line(rtu);
  }

  RtuConfig rtu_line(const YAML::Node& node) const {
    yaml_.expect_keys(node, "modbus.rtu", {"device", "baud", "parity", "stop_bits", "rs485", "low_latency"});
    RtuConfig r;
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

  void mapping(const YAML::Node& node) {
    yaml_.expect_keys(node, "mapping", {"A", "B", "user_inputs", "user_outputs"});
    auto& m = config_.mapping;
    if (node["A"]) mapping_list(node["A"], "A", SourceUse::analog, m.analog);
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
        yaml_.expect_keys(b, "a poll block", {"type", "device", "register", "period", "output"});
      } else {
        block.type = Block::Type::send;
        yaml_.expect_keys(b, "a send block", {"type", "device", "register", "period", "source"});
      }
      const auto required = [&](const char* key) {
        if (!b[key]) yaml_.fail(b, fmt::format("a {} block needs '{}'", type, key));
        return b[key];
      };
      block.reg = static_cast<std::uint16_t>(yaml_.number(required("register"), 0, 0xFFFF));
      if (block.type == Block::Type::read || block.type == Block::Type::send)
        block.source = source(required("source"), SourceUse::analog);
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
      }
      config_.blocks.push_back(std::move(block));
    }
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
    }
    if (node["stdout"]) m.to_stdout = yaml_.boolean(node["stdout"]);
    if (node["format"]) m.format = yaml_.choice(node["format"], {"text", "json"}) == "json" ? MonitorFormat::json : MonitorFormat::text;
    if (node["max_size"]) m.max_size = yaml_.byte_size(node["max_size"], 4096, 1ull << 40);
    if (node["max_files"]) m.max_files = static_cast<unsigned>(yaml_.number(node["max_files"], 1, 100));
    if (node["queue"]) m.queue = static_cast<unsigned>(yaml_.number(node["queue"], 16, 1'000'000));
    if (const auto filter = node["filter"]) {
      yaml_.expect_keys(filter, "monitor.filter", {"address", "function", "from", "to"});
      const auto any_or_byte = [&](const YAML::Node& value) -> std::optional<std::uint8_t> {
        if (value.IsScalar() && (value.Scalar() == "xx" || value.Scalar() == "XX")) return std::nullopt;
        return static_cast<std::uint8_t>(yaml_.number(value, 0, 255));
      };
      if (filter["address"]) m.filter.address = any_or_byte(filter["address"]);
      if (filter["function"]) m.filter.function = any_or_byte(filter["function"]);
      if (filter["from"]) m.filter.from = static_cast<std::uint16_t>(yaml_.number(filter["from"], 0, 0xFFFF));
      if (filter["to"]) m.filter.to = static_cast<std::uint16_t>(yaml_.number(filter["to"], 0, 0xFFFF));
      if (m.filter.from > m.filter.to)
        yaml_.fail(filter["to"] ? filter["to"] : filter["from"],
                   fmt::format("monitor.filter: 'to' (0x{:04X}) is before 'from' (0x{:04X})", m.filter.to, m.filter.from));
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

  void status(const YAML::Node& node) {
    yaml_.expect_keys(node, "status", {"socket"});
    if (node["socket"]) {
      auto& socket = config_.status.socket;
      socket = yaml_.text(node["socket"]);
      // sockaddr_un holds 108 bytes with the terminating zero.
      if (socket.empty() || socket.size() > 107)
        yaml_.fail(node["socket"], "status.socket must be a path of 1..107 characters (a unix socket's limit)");
    }
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
  banks::BankShapes shapes_{};
};

}  // namespace

Config load_text(const std::string& text, const std::string& origin) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::ParserException& e) {
    throw ConfigError(fmt::format("{}:{}:{}: {}", origin, e.mark.line + 1, e.mark.column + 1, e.msg));
  }
  try {
    return Loader(origin).load(root);
  } catch (const YAML::Exception& e) {
    throw ConfigError(fmt::format("{}:{}:{}: {}", origin, e.mark.line + 1, e.mark.column + 1, e.msg));
  }
}

Config load_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ConfigError(fmt::format("{}: cannot open the config file: {}", path, std::strerror(errno)));
  std::ostringstream text;
  text << in.rdbuf();
  return load_text(text.str(), path);
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

std::vector<const Block*> Config::active_blocks() const {
  std::vector<const Block*> active;
  for (const auto& block : blocks)
    if (block.is_slave_block() == (modbus.mode == ModbusMode::slave)) active.push_back(&block);
  return active;
}

std::vector<std::string> warnings(const Config& config) {
  std::vector<std::string> found;
  const bool slave = config.modbus.mode == ModbusMode::slave;
  for (const auto& block : config.blocks) {
    if (block.is_slave_block() != slave)
      found.push_back(fmt::format("{}: {} block ignored: {} blocks act in {} mode only, this bridge is a {}",
                                  block.origin, block_type_name(block.type), block_type_name(block.type),
                                  block.is_slave_block() ? "slave" : "master", slave ? "slave" : "master"));
    else if (block.type == Block::Type::capture && !config.modbus.rtu)
      found.push_back(fmt::format("{}: capture block inactive: capture listens on a Modbus RTU line, and "
                                  "modbus.rtu is not set", block.origin));
  }
  return found;
}

}  // namespace unima::config
