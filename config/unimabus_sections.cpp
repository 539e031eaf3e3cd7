// The UnimaBUS side (unimabus: transport, replay, record, sim, the feed's listen) and the
// files and socket the bridge keeps on this machine (log, monitor, status, state).

#include <filesystem>

#include <fmt/format.h>

#include "config/endpoint.hpp"
#include "config/section_parsers.hpp"
#include "monitor/command_filter.hpp"

namespace unima::config::sections {

namespace {

// The replay transport's keys. Its recording is read by check_on_host, so that `check` and
// a reload see a bad line before anything starts (SPEC §6).
void parse_replay(ParseState& state, const YAML::Node& node) {
  const auto& yaml = state.yaml;
  auto& r = state.config.unimabus.replay;
  const bool replaying = state.config.unimabus.transport == TransportKind::replay;
  for (const char* key : {"file", "loop", "speed"})
    if (node[key] && !replaying) yaml.fail(node[key], fmt::format("'{}' is a key of the replay transport", key));
  if (!replaying) return;
  if (!node["file"]) yaml.fail(node, "the replay transport needs 'file', the recording to play");
  r.file = yaml.text(node["file"]);
  r.file_origin = yaml.position(node["file"]);
  if (node["loop"]) r.loop = yaml.boolean(node["loop"]);
  if (node["speed"]) {
    r.speed = yaml.decimal(node["speed"]);
    if (r.speed < 0.001 || r.speed > 1000) yaml.fail(node["speed"], "speed must be 0.001..1000 (1 plays in real time)");
  }
}

void parse_record(ParseState& state, const YAML::Node& record) {
  const auto& yaml = state.yaml;
  auto& r = state.config.unimabus.record;
  yaml.expect_keys(record, "unimabus.record", {"file", "max_size", "max_files"});
  if (!record["file"]) yaml.fail(record, "unimabus.record needs the file to record to");
  r.file = yaml.text(record["file"]);
  if (r.file.empty()) yaml.fail(record["file"], "unimabus.record.file must name a file");
  note_host_path(state, HostPath::Use::log_file, record["file"], "unimabus.record.file", r.file);
  if (record["max_size"]) r.max_size = yaml.byte_size(record["max_size"], 4096, 1ull << 40);
  if (record["max_files"]) r.max_files = static_cast<unsigned>(yaml.number(record["max_files"], 1, 100));
}

void parse_sim(ParseState& state, const YAML::Node& sim) {
  const auto& yaml = state.yaml;
  auto& s = state.config.unimabus.sim;
  yaml.expect_keys(sim, "unimabus.sim", {"seed", "period", "io_modules"});
  if (sim["seed"]) s.seed = static_cast<std::uint32_t>(yaml.number(sim["seed"], 0, 0xFFFFFFFF));
  if (sim["period"]) {
    s.period = yaml.duration(sim["period"]);
    if (s.period < Duration(10)) yaml.fail(sim["period"], "the simulator period must be at least 10ms");
  }
  if (const auto modules = sim["io_modules"]) {
    if (!modules.IsSequence()) yaml.fail(modules, "io_modules must be a list of slots 1..7");
    for (const auto& slot : modules) s.io_modules.push_back(static_cast<unsigned>(yaml.number(slot, 1, 7)));
  }
}

void parse_feed_listen(ParseState& state, const YAML::Node& node) {
  auto& u = state.config.unimabus;
  auto parsed = parse_listen_endpoint(u.listen);
  if (auto* error = std::get_if<std::string>(&parsed)) state.yaml.fail(node, *error);
  u.listen_at = std::get<ListenEndpoint>(std::move(parsed));
  u.listen_origin = state.yaml.position(node);
  if (u.listen_at.is_unix())
    note_host_path(state, HostPath::Use::unix_socket, node, "unimabus.listen", u.listen_at.unix_path);
}

// The same fields as the command line's --filter (monitor/command_filter).
void parse_monitor_filter(const YamlReader& yaml, const YAML::Node& filter, monitor::CommandFilter& into) {
  yaml.expect_keys(filter, "monitor.filter", {"address", "function", "from", "to"});
  using monitor::FilterField;
  for (const auto& [key, field] : {std::pair{"address", FilterField::address}, std::pair{"function", FilterField::function},
                                   std::pair{"from", FilterField::from}, std::pair{"to", FilterField::to}}) {
    const auto value = filter[key];
    if (!value) continue;
    try {
      monitor::set_filter_field(into, field, yaml.text(value));
    } catch (const monitor::FilterSyntaxError& e) {
      yaml.fail(value, fmt::format("monitor.filter: {}", e.what()));
    }
  }
  try {
    monitor::check_filter_range(into);
  } catch (const monitor::FilterSyntaxError& e) {
    yaml.fail(filter["to"] ? filter["to"] : filter["from"], fmt::format("monitor.filter: {}", e.what()));
  }
}

}  // namespace

// systemd's StateDirectory= is where a service keeps its state; $STATE_DIRECTORY lists its
// directories separated by colons. Outside the service the state goes beside the config.
std::string default_state_path(const std::string& config_file, const Host& host, std::string_view name) {
  if (const auto directories = host.environment("STATE_DIRECTORY"); !directories.empty())
    return directories.substr(0, directories.find(':')) + "/" + std::string(name);
  return std::filesystem::path(config_file).replace_extension("." + std::string(name)).string();
}

void note_host_path(ParseState& state, HostPath::Use use, const YAML::Node& node, std::string key, std::string path) {
  state.config.host_paths.push_back({use, std::move(key), std::move(path), state.yaml.position(node), {}});
}

void parse_unimabus(ParseState& state, const YAML::Node& node) {
  const auto& yaml = state.yaml;
  yaml.expect_keys(node, "unimabus",
                   {"address", "transport", "listen", "max_clients", "offline_after", "sim", "file", "loop", "speed",
                    "record"});
  auto& u = state.config.unimabus;
  if (node["address"]) u.address = static_cast<std::uint8_t>(yaml.number(node["address"], 0, 255));
  if (node["transport"]) {
    const auto t = yaml.choice(node["transport"], {"sim", "feed", "replay"});
    u.transport = t == "feed" ? TransportKind::feed : t == "replay" ? TransportKind::replay : TransportKind::sim;
  }
  parse_replay(state, node);
  if (node["record"]) parse_record(state, node["record"]);
  if (node["listen"]) u.listen = yaml.text(node["listen"]);
  if (node["max_clients"]) u.max_clients = static_cast<unsigned>(yaml.number(node["max_clients"], 1, 1000));
  if (node["offline_after"]) {
    u.offline_after = yaml.duration(node["offline_after"]);
    if (u.offline_after.count() == 0) yaml.fail(node["offline_after"], "offline_after must be longer than 0");
  }
  if (node["sim"]) parse_sim(state, node["sim"]);
  if (u.transport == TransportKind::feed) {
    if (u.listen.empty()) yaml.fail(node, "the feed transport needs 'listen' (host:port or unix:/path)");
    parse_feed_listen(state, node["listen"]);
  } else if (node["listen"]) {
    yaml.fail(node["listen"], "'listen' belongs to the feed transport only");
  }
}

void parse_log(ParseState& state, const YAML::Node& node) {
  state.yaml.expect_keys(node, "log", {"level"});
  if (node["level"])
    state.config.log.level =
        state.yaml.choice(node["level"], {"trace", "debug", "info", "warn", "error", "critical", "off"});
}

void parse_monitor(ParseState& state, const YAML::Node& node) {
  const auto& yaml = state.yaml;
  yaml.expect_keys(node, "monitor", {"file", "stdout", "format", "max_size", "max_files", "queue", "filter", "indicators"});
  auto& m = state.config.monitor;
  if (node["file"]) {
    m.file = yaml.text(node["file"]);
    if (m.file.empty()) yaml.fail(node["file"], "monitor.file must name a file");
    note_host_path(state, HostPath::Use::log_file, node["file"], "monitor.file", m.file);
  }
  if (node["stdout"]) m.to_stdout = yaml.boolean(node["stdout"]);
  if (node["format"])
    m.format = yaml.choice(node["format"], {"text", "json"}) == "json" ? monitor::MonitorFormat::json
                                                                        : monitor::MonitorFormat::text;
  if (node["max_size"]) m.max_size = yaml.byte_size(node["max_size"], 4096, 1ull << 40);
  if (node["max_files"]) m.max_files = static_cast<unsigned>(yaml.number(node["max_files"], 1, 100));
  if (node["queue"]) m.queue = static_cast<unsigned>(yaml.number(node["queue"], 16, 1'000'000));
  if (node["filter"]) parse_monitor_filter(yaml, node["filter"], m.filter);
  if (const auto indicators = node["indicators"]) {
    if (!indicators.IsSequence()) yaml.fail(indicators, "indicators must be a list of { address, register }");
    for (const auto& entry : indicators) {
      if (m.indicators.size() == 4) yaml.fail(entry, "at most 4 capture indicators (seed 004 §8)");
      yaml.expect_keys(entry, "an indicator", {"address", "register"});
      if (!entry["address"] || !entry["register"]) yaml.fail(entry, "an indicator needs an address and a register");
      m.indicators.push_back({static_cast<std::uint8_t>(yaml.number(entry["address"], 0, 255)),
                              yaml.register_address(entry["register"])});
    }
  }
}

void parse_status(ParseState& state, const YAML::Node& node, const YAML::Node& root) {
  const auto& yaml = state.yaml;
  auto& socket = state.config.status.socket;
  if (node) yaml.expect_keys(node, "status", {"socket"});
  if (!node || !node["socket"])
    return note_host_path(state, HostPath::Use::unix_socket, node ? node : root, "status.socket", socket);
  socket = yaml.text(node["socket"]);
  if (const auto error = socket_path_error(socket)) yaml.fail(node["socket"], fmt::format("status.socket {}", *error));
  note_host_path(state, HostPath::Use::unix_socket, node["socket"], "status.socket", socket);
}

void parse_state(ParseState& state, const YAML::Node& node, const YAML::Node& root) {
  const auto& yaml = state.yaml;
  auto& file = state.config.state.file;
  file = default_state_path(state.in_place_of, state.host, "state");
  if (node) yaml.expect_keys(node, "state", {"file"});
  if (!node || !node["file"]) return note_host_path(state, HostPath::Use::state_file, node ? node : root, "state.file", file);
  const auto written = yaml.text(node["file"]);
  if (written.empty()) yaml.fail(node["file"], "state.file must be a path, or none to keep no state");
  file = written == "none" ? std::string() : written;
  if (!file.empty()) note_host_path(state, HostPath::Use::state_file, node["file"], "state.file", file);
}

}  // namespace unima::config::sections
