// What a parsed Config tells beyond its fields: the blocks that act in its mode, a line's
// timing, and the warnings for the log at start and for `unima-bridge check`.

#include <fmt/format.h>

#include "config/config.hpp"
#include "config/master_setup.hpp"

namespace unima::config {

char parity_letter(Parity parity) {
  switch (parity) {
    case Parity::even: return 'E';
    case Parity::odd: return 'O';
    case Parity::none: break;
  }
  return 'N';
}

modbus::RtuTiming line_timing(const RtuConfig& line) {
  return modbus::rtu_timing(line.baud, line.parity != Parity::none, line.stop_bits);
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

const LineConfig* ModbusConfig::line_of(LineRole role) const {
  for (const auto& line : lines)
    if (line.role == role) return &line;
  return nullptr;
}

const LineConfig* ModbusConfig::find_line(std::string_view name) const {
  for (const auto& line : lines)
    if (line.name == name) return &line;
  return nullptr;
}

bool ModbusConfig::serves_slave_blocks() const { return mode == ModbusMode::slave || line_of(LineRole::slave); }

const GatewayConfig* ModbusConfig::gateway() const {
  const auto* line = line_of(LineRole::master);
  return line && line->gateway ? &*line->gateway : nullptr;
}

std::optional<GatewayRoutes> ModbusConfig::gateway_routes() const {
  GatewayRoutes routes;
  for (const auto& line : lines) {
    if (line.role != LineRole::master || !line.gateway) continue;
    const auto index = static_cast<std::uint8_t>(routes.gateways.size());
    routes.gateways.emplace_back(line.name, *line.gateway);
    for (unsigned unit = 0; unit < 256; ++unit)
      if (line.gateway->units[unit]) {
        routes.units[unit] = true;
        routes.gateway_of[unit] = index;
      }
  }
  if (routes.gateways.empty()) return std::nullopt;
  return routes;
}

std::vector<const LineConfig*> ModbusConfig::lines_of(LineRole role) const {
  std::vector<const LineConfig*> found;
  for (const auto& line : lines)
    if (line.role == role) found.push_back(&line);
  return found;
}

std::string_view ModbusConfig::shown_name(const LineConfig& line) const {
  return lines.size() > 1 ? std::string_view(line.name) : std::string_view();
}

namespace {

bool block_acts(const ModbusConfig& modbus, const Block& block) {
  return block.is_slave_block() ? modbus.serves_slave_blocks() : modbus.mode == ModbusMode::master;
}

}  // namespace

std::vector<const Block*> Config::active_blocks() const {
  std::vector<const Block*> active;
  for (const auto& block : blocks)
    if (block_acts(modbus, block)) active.push_back(&block);
  return active;
}

std::string unit_ranges_text(const GatewayConfig& gateway) {
  std::string text;
  for (unsigned first = 1; first <= 247; ++first) {
    if (!gateway.units[first]) continue;
    auto last = first;
    while (last < 247 && gateway.units[last + 1]) ++last;
    text += (text.empty() ? "" : ", ") + (last == first ? std::to_string(first) : fmt::format("{}-{}", first, last));
    first = last;
  }
  return text;
}

bool writes_frozen(const Config& config) { return config.modbus.tcp && config.modbus.tcp->read_only; }

std::string warning_text(std::string_view origin, std::string_view message) {
  return fmt::format("{}: warning: {}", origin, message);
}

std::vector<std::string> warnings(const Config& config) {
  std::vector<std::string> found;
  const bool slave = config.modbus.mode == ModbusMode::slave;
  if (slave && !config.modbus.master.origin.empty())
    found.push_back(warning_text(config.modbus.master.origin,
                                 "modbus.master is set, but this bridge is a slave; the master settings are unused"));
  for (const auto& block : config.blocks) {
    if (!block_acts(config.modbus, block))
      found.push_back(warning_text(block.origin, fmt::format("{} block ignored: {} blocks act in {} mode only, this bridge is a {}",
                                                             block_type_name(block.type), block_type_name(block.type),
                                                             block.is_slave_block() ? "slave" : "master",
                                                             slave ? "slave" : "master")));
    else if (block.type == Block::Type::capture && block.line.empty())
      found.push_back(warning_text(block.origin, "capture block inactive: capture listens on a Modbus RTU line, and "
                                                 "modbus.rtu is not set"));
  }
  if (const auto& http = config.http; http && !is_loopback_address(http->listen)) {
    if (http->users.empty())
      found.push_back(warning_text(http->origin, fmt::format("http listens on {} without http.users: anyone who reaches the "
                                                             "port reads the plant's values and the monitor", http->listen)));
    else if (!http->tls)
      found.push_back(warning_text(http->origin, fmt::format("http listens on {} without http.tls: passwords cross the "
                                                             "network in clear", http->listen)));
  }
  if (config.mqtt && config.mqtt->commands && writes_frozen(config))
    found.push_back(warning_text(config.mqtt->origin, "mqtt.commands is true, but modbus.tcp.read_only is on: every MQTT "
                                                      "command is refused (ok: false on set/result) while it is"));
  if (config.sparkplug && config.sparkplug->commands && writes_frozen(config))
    found.push_back(warning_text(config.sparkplug->origin, "sparkplug.commands is true, but modbus.tcp.read_only is on: "
                                                           "every DCMD is refused (counted) while it is"));
  if (!slave) {
    const auto more = foreign_slave_warnings(config);
    found.insert(found.end(), more.begin(), more.end());
  }
  found.insert(found.end(), config.noted_warnings.begin(), config.noted_warnings.end());
  return found;
}

Duration max_report_interval(const Config& config) {
  if (config.report.max_interval) return *config.report.max_interval;
  return config.mqtt ? config.mqtt->period : MqttConfig{}.period;
}

}  // namespace unima::config
