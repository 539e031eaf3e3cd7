// What listens on the network or connects to it, besides the feed: the Modbus TCP and TLS
// slaves, the HTTP server, the MQTT client. A listen address and a PEM file are read by
// one function each, whichever section holds them.

#include <algorithm>
#include <array>
#include <optional>
#include <string_view>
#include <tuple>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "config/endpoint.hpp"
#include "config/section_parsers.hpp"
#include "config/topic_filter.hpp"

namespace unima::config::sections {

namespace {

constexpr std::array<std::string_view, 7> tcp_keys = {"listen",        "port",  "max_clients", "idle_timeout",
                                                       "frame_timeout", "allow", "read_only"};

// Where a server listens: an IP address of this machine (config/endpoint) and a port,
// 0 for any free one.
void parse_listen_address(const YamlReader& yaml, const YAML::Node& section, std::string& listen,
                          std::uint16_t& port, std::string& port_origin) {
  if (section["listen"]) {
    listen = yaml.text(section["listen"]);
    if (const auto error = listen_address_error(listen, HostRule::listen_address)) yaml.fail(section["listen"], *error);
  }
  if (section["port"]) port = static_cast<std::uint16_t>(yaml.number(section["port"], 0, 65535));
  port_origin = yaml.position(section["port"] ? section["port"] : section);
}

// A PEM file the daemon loads: what is in it is check_on_host's question (tls/pem_check),
// at start, on reload and in `check`, each key named at its own line.
void note_pem_file(ParseState& state, const YAML::Node& node, std::string key, HostPath::Use use, std::string& file) {
  file = state.yaml.text(node);
  if (file.empty()) state.yaml.fail(node, fmt::format("{} must be the path of a PEM file", key));
  note_host_path(state, use, node, std::move(key), file);
}

// A TLS server's PEM files: its certificate, its key (which must belong to it), and for
// Modbus/TCP Security the CA of its clients. `section` names them in messages.
void parse_server_pem_files(ParseState& state, const YAML::Node& node, std::string_view section, std::string& certificate,
                            std::string& key, std::string* ca) {
  for (const char* name : {"certificate", "key", "ca"}) {
    if (!node[name] && (ca || std::string_view(name) != "ca"))
      state.yaml.fail(node, fmt::format("{} needs '{}', a PEM file", section, name));
  }
  note_pem_file(state, node["certificate"], fmt::format("{}.certificate", section), HostPath::Use::certificate, certificate);
  note_pem_file(state, node["key"], fmt::format("{}.key", section), HostPath::Use::private_key, key);
  state.config.host_paths.back().certificate = fmt::format("{}.certificate", section);
  if (ca) note_pem_file(state, node["ca"], fmt::format("{}.ca", section), HostPath::Use::ca_certificates, *ca);
}


// The keys modbus.tcp and modbus.tls share; `key` names the section in messages.
TcpSlaveConfig parse_tcp_slave(const YamlReader& yaml, const YAML::Node& node, std::string_view key, TcpSlaveConfig t) {
  parse_listen_address(yaml, node, t.listen, t.port, t.port_origin);
  if (node["max_clients"]) t.max_clients = static_cast<unsigned>(yaml.number(node["max_clients"], 1, 10000));
  if (node["idle_timeout"]) t.idle_timeout = yaml.duration(node["idle_timeout"]);
  if (node["frame_timeout"]) {
    t.frame_timeout = yaml.duration(node["frame_timeout"]);
    if (t.frame_timeout.count() <= 0) yaml.fail(node["frame_timeout"], fmt::format("{}.frame_timeout must be above 0", key));
  }
  if (node["allow"]) t.allow = parse_allow_list(yaml, node["allow"], fmt::format("{}.allow", key));
  if (node["read_only"]) t.read_only = yaml.boolean(node["read_only"]);
  return t;
}

// A role's "unit 3" or "units 5-9": the ids after the word, or nullopt for an item that is
// not one (a bank or a register).
std::optional<std::string_view> unit_words(std::string_view text) {
  if (!text.starts_with("unit")) return std::nullopt;
  text.remove_prefix(text.starts_with("units") ? 5 : 4);
  while (!text.empty() && text.front() == ' ') text.remove_prefix(1);
  return text;
}

// A right to write to a unit that the gateway does not forward is never used: the request
// gets 0x0A before anyone asks for rights. Not an error (the gateway's units may be cut
// down on purpose for a while), but said, at the item.
void warn_units_not_routed(const YamlReader& yaml, const YAML::Node& item, std::string_view key, unsigned first,
                           unsigned last, const GatewayRoutes* gateway) {
  std::vector<unsigned> unrouted;
  for (auto unit = first; unit <= last; ++unit)
    if (!gateway || !gateway->units[unit]) unrouted.push_back(unit);
  if (unrouted.empty()) return;
  const auto which = unrouted.size() == 1 ? fmt::format("unit {} is", unrouted.front())
                     : unrouted.size() == last - first + 1 ? fmt::format("units {}-{} are", first, last)
                                                            : fmt::format("units {} are", fmt::join(unrouted, ", "));
  yaml.warn(item, gateway ? fmt::format("{}: {} not in modbus.gateway.units; no request reaches {} and this right is "
                                        "never used",
                                        key, which, unrouted.size() == 1 ? "it" : "them")
                          : fmt::format("{}: {} named, but there is no modbus.gateway; this right is never used", key,
                                        which));
}

// A role's `write: [W, X, 0x0201, "unit 3", "units 5-9"]`: banks by name, registers by
// address, and the foreign slaves behind the gateway it may send writes to (SPEC §14).
modbus::WriteRights parse_role(const YamlReader& yaml, const std::string& name, const YAML::Node& node,
                               const banks::AddressMap& map, const GatewayRoutes* gateway) {
  if (!node.IsMap()) yaml.fail(node, fmt::format("modbus.tls.roles.{} must be {{ write: [...] }}", name));
  yaml.expect_keys(node, fmt::format("modbus.tls.roles.{}", name), {"write"});
  auto rights = modbus::WriteRights::nothing();
  const auto write = node["write"];
  if (!write) return rights;
  if (!write.IsSequence())
    yaml.fail(write, fmt::format("modbus.tls.roles.{}.write must be a list of banks, registers and units, e.g. "
                                 "[W, X, 0x0201, \"unit 3\"]",
                                 name));
  for (const auto& item : write) {
    const auto text = yaml.text(item);
    if (const auto units = unit_words(text)) {
      const auto [first, last] = parse_unit_range(yaml, item, *units, fmt::format("modbus.tls.roles.{}.write", name),
                                                  "\"unit 3\" or \"units 5-9\"");
      rights.allow_units(first, last);
      warn_units_not_routed(yaml, item, fmt::format("modbus.tls.roles.{}.write", name), first, last, gateway);
    } else if (const auto bank = banks::parse_bank_name(text)) {
      const auto window = std::find_if(map.windows().begin(), map.windows().end(), [&](const banks::Window& w) {
        return w.kind == banks::Window::Kind::bank && w.bank == *bank;
      });
      if (window == map.windows().end()) yaml.fail(item, fmt::format("bank {} is not served by this config", text));
      rights.allow(window->first, static_cast<std::uint16_t>(window->end() - 1));
    } else {
      const auto address = yaml.register_address(item);
      if (!map.find(address)) yaml.fail(item, fmt::format("register {:#06x} is in no bank or block of this config", address));
      rights.allow(address, address);
    }
  }
  return rights;
}

}  // namespace

PeerAllowList parse_allow_list(const YamlReader& yaml, const YAML::Node& node, std::string_view key) {
  if (!node.IsSequence() || node.size() == 0)
    yaml.fail(node, fmt::format("{} must be a list of addresses and CIDR ranges, e.g. [192.168.10.0/24, 127.0.0.1]", key));
  PeerAllowList list;
  for (const auto& item : node) {
    auto parsed = parse_network_range(yaml.text(item));
    if (auto* error = std::get_if<std::string>(&parsed)) yaml.fail(item, fmt::format("{}: {}", key, *error));
    list.ranges.push_back(std::get<NetworkRange>(std::move(parsed)));
  }
  return list;
}

TcpSlaveConfig parse_modbus_tcp(ParseState& state, const YAML::Node& node) {
  state.yaml.expect_keys(node, "modbus.tcp", tcp_keys);
  return parse_tcp_slave(state.yaml, node, "modbus.tcp", TcpSlaveConfig{});
}

TlsSlaveConfig parse_modbus_tls(ParseState& state, const YAML::Node& node) {
  const auto& yaml = state.yaml;
  std::vector<std::string_view> keys(tcp_keys.begin(), tcp_keys.end());
  for (const char* k : {"certificate", "key", "ca", "roles"}) keys.push_back(k);
  yaml.expect_keys(node, "modbus.tls", keys);
  TlsSlaveConfig tls;
  tls.origin = yaml.position(node);
  tls.connection = parse_tcp_slave(yaml, node, "modbus.tls", TlsSlaveConfig::default_connection());
  parse_server_pem_files(state, node, "modbus.tls", tls.certificate, tls.key, &tls.ca);
  if (const auto roles = node["roles"]) {
    if (!roles.IsMap()) yaml.fail(roles, "modbus.tls.roles must map each role to { write: [...] }");
    for (const auto& role : roles) state.tls_roles.emplace_back(yaml.text(role.first), role.second);
  }
  return tls;
}

void resolve_tls_roles(ParseState& state) {
  auto& tls = state.config.modbus.tls;
  if (!tls) return;
  const auto map = address_map(state.config);
  // Every master line's units: a right to write to a unit any line routes is used.
  const auto routes = state.config.modbus.gateway_routes();
  for (const auto& [name, node] : state.tls_roles)
    tls->roles.insert_or_assign(name, parse_role(state.yaml, name, node, map, routes ? &*routes : nullptr));
}

void parse_http(ParseState& state, const YAML::Node& node) {
  const auto& yaml = state.yaml;
  yaml.expect_keys(node, "http", {"listen", "port", "max_clients", "tls", "users"});
  HttpConfig h;
  h.origin = yaml.position(node);
  parse_listen_address(yaml, node, h.listen, h.port, h.port_origin);
  if (node["max_clients"]) h.max_clients = static_cast<unsigned>(yaml.number(node["max_clients"], 1, 1000));
  if (const auto tls = node["tls"]) {
    yaml.expect_keys(tls, "http.tls", {"certificate", "key"});
    HttpTlsConfig t;
    parse_server_pem_files(state, tls, "http.tls", t.certificate, t.key, nullptr);
    h.tls = t;
  }
  if (const auto users = node["users"]) {
    if (!users.IsScalar())
      yaml.fail(users, "http.users must be the path of a file of name:password-hash lines, not the users themselves "
                       "(docs/security.md: make the hashes with `openssl passwd -6`)");
    h.users = yaml.text(users);
    h.users_origin = yaml.position(users);
    if (h.users.empty()) yaml.fail(users, "http.users must be the path of a file of name:password-hash lines");
  }
  state.config.http = h;
}

namespace {

// mqtt.buffer (SPEC §15): on by default, beside the state file; `file: none` turns it off.
void parse_mqtt_buffer(ParseState& state, const YAML::Node& mqtt, MqttBufferConfig& buffer) {
  const auto& yaml = state.yaml;
  const auto node = mqtt["buffer"];
  if (node && !node.IsMap()) yaml.fail(node, "mqtt.buffer must be a mapping, e.g. { file: /var/lib/unima-bridge/mqtt-buffer, max_size: 64MiB }");
  if (node) yaml.expect_keys(node, "mqtt.buffer", {"file", "max_size"});
  if (node && node["max_size"]) buffer.max_size = yaml.byte_size(node["max_size"], 4096, 1ull << 40);
  if (!node || !node["file"]) {
    buffer.file = default_state_path(state.in_place_of, state.host, "mqtt-buffer");
    return note_host_path(state, HostPath::Use::state_file, node ? node : mqtt, "mqtt.buffer.file", buffer.file);
  }
  const auto written = yaml.text(node["file"]);
  if (written.empty()) yaml.fail(node["file"], "mqtt.buffer.file must be a path, or none to keep no history");
  buffer.file = written == "none" ? std::string() : written;
  if (buffer.file.empty()) return;
  if (buffer.file == state.config.state.file)
    yaml.fail(node["file"], "mqtt.buffer.file is the state file; each needs a file of its own");
  note_host_path(state, HostPath::Use::state_file, node["file"], "mqtt.buffer.file", buffer.file);
}

constexpr std::array<std::string_view, 7> broker_keys = {"broker", "username", "password_file", "ca",
                                                          "certificate", "key", "version"};

std::vector<std::string_view> keys_with_broker(std::initializer_list<std::string_view> own) {
  std::vector<std::string_view> keys(broker_keys.begin(), broker_keys.end());
  keys.insert(keys.end(), own.begin(), own.end());
  return keys;
}

// How a section reaches its broker — the URL, TLS files, credentials, protocol version —
// read alike for mqtt and sparkplug (both configs name these fields the same), `section`
// naming the keys in messages.
template <typename Section>
void parse_broker_connection(ParseState& state, const YAML::Node& node, std::string_view section, Section& s) {
  const auto& yaml = state.yaml;
  if (!node["broker"])
    yaml.fail(node, fmt::format("{} needs 'broker', e.g. mqtt://127.0.0.1:1883 or mqtts://broker.example:8883", section));
  s.broker = yaml.text(node["broker"]);
  auto broker = parse_mqtt_broker(s.broker);
  if (auto* error = std::get_if<std::string>(&broker)) yaml.fail(node["broker"], fmt::format("{}.broker: {}", section, *error));
  s.tls = std::get<MqttBroker>(broker).tls;
  s.endpoint = std::get<MqttBroker>(broker).endpoint;
  if (node["username"]) s.username = yaml.text(node["username"]);
  if (node["password_file"]) s.password_file = yaml.text(node["password_file"]);
  if (!s.password_file.empty() && s.username.empty())
    yaml.fail(node["password_file"], fmt::format("{0}.password_file needs {0}.username", section));
  using Use = HostPath::Use;
  if (!s.password_file.empty())
    note_host_path(state, Use::secret_file, node["password_file"], std::string(section) + ".password_file", s.password_file);
  for (const auto& [key, use, file] : {std::tuple{"ca", Use::ca_certificates, &s.ca},
                                       std::tuple{"certificate", Use::certificate, &s.certificate},
                                       std::tuple{"key", Use::private_key, &s.key}}) {
    if (!node[key]) continue;
    if (!s.tls) yaml.fail(node[key], fmt::format("{}.{} is for mqtts:// brokers", section, key));
    note_pem_file(state, node[key], fmt::format("{}.{}", section, key), use, *file);
  }
  if (s.certificate.empty() != s.key.empty())
    yaml.fail(node, fmt::format("{0}.certificate and {0}.key go together (the client's certificate and its key)", section));
  if (!s.key.empty()) state.config.host_paths.back().certificate = fmt::format("{}.certificate", section);
  if (node["version"]) {
    const auto version = yaml.text(node["version"]);
    if (version == "3.1.1") s.version = 4;
    else if (version == "5") s.version = 5;
    else yaml.fail(node["version"], fmt::format("{}.version must be 3.1.1 or 5", section));
  }
}

// An MQTT client id: 1..64 characters, `fallback` when the section names none.
std::string parse_client_id(const YamlReader& yaml, const YAML::Node& node, std::string_view section, std::string fallback) {
  auto id = node["client_id"] ? yaml.text(node["client_id"]) : std::move(fallback);
  if (id.empty() || id.size() > 64)
    yaml.fail(node["client_id"] ? node["client_id"] : node, fmt::format("{}.client_id must be 1..64 characters", section));
  return id;
}

// A Sparkplug id (group, edge node, host) is one level of a topic (Sparkplug 3.0 §4.1.1):
// no separator, no wildcard.
std::string parse_sparkplug_id(const YamlReader& yaml, const YAML::Node& node, std::string_view key) {
  auto id = yaml.text(node);
  if (id.empty() || id.find_first_of("/#+") != std::string::npos)
    yaml.fail(node, fmt::format("sparkplug.{} must be a name without / # or +", key));
  return id;
}

// mqtt.response_topics: a list of MQTT topic filters, absent: `<prefix>/reply/#`.
std::vector<std::string> parse_response_topics(const YamlReader& yaml, const YAML::Node& node, const std::string& prefix) {
  if (!node) return {prefix + "/reply/#"};
  if (!node.IsSequence())
    yaml.fail(node, fmt::format("mqtt.response_topics must be a list of topic filters, e.g. [{}/reply/#]", prefix));
  std::vector<std::string> filters;
  for (const auto& item : node) {
    auto filter = yaml.text(item);
    if (const auto problem = topic_filter_problem(filter))
      yaml.fail(item, fmt::format("mqtt.response_topics: not a topic filter: {}", *problem));
    filters.push_back(std::move(filter));
  }
  return filters;
}

}  // namespace

void parse_mqtt(ParseState& state, const YAML::Node& node) {
  const auto& yaml = state.yaml;
  yaml.expect_keys(node, "mqtt", keys_with_broker({"client_id", "topic", "publish", "commands", "response_topics",
                                                   "discovery", "buffer"}));
  MqttConfig m;
  m.origin = yaml.position(node);
  parse_broker_connection(state, node, "mqtt", m);
  m.host_name = state.host.name;
  m.machine_id = state.host.machine_id;
  m.client_id = parse_client_id(yaml, node, "mqtt", default_client_id(m.host_name, m.machine_id));
  if (!node["client_id"] && m.machine_id.empty())
    yaml.warn(node, fmt::format("mqtt.client_id: this machine has no {} (machine-id(5)), so the default client id is {} "
                                "without one: bridges of one cloned image would share it and take the broker's session "
                                "from each other; set mqtt.client_id",
                                machine_id_file, m.client_id));
  m.topic = node["topic"] ? yaml.text(node["topic"]) : "unima/" + m.client_id;
  if (m.topic.empty() || m.topic.back() == '/' || m.topic.find_first_of("#+") != std::string::npos)
    yaml.fail(node["topic"] ? node["topic"] : node, "mqtt.topic must be a topic prefix without wildcards (# +) or a trailing /");
  if (const auto publish = node["publish"]) {
    yaml.expect_keys(publish, "mqtt.publish", {"period", "on_change"});
    if (publish["period"]) {
      m.period = yaml.duration(publish["period"]);
      if (m.period < std::chrono::seconds(1)) yaml.fail(publish["period"], "mqtt.publish.period must be 1s or more");
    }
    if (publish["on_change"]) m.on_change = yaml.boolean(publish["on_change"]);
  }
  if (node["commands"]) m.commands = yaml.boolean(node["commands"]);
  m.response_topics = parse_response_topics(yaml, node["response_topics"], m.topic);
  if (const auto discovery = node["discovery"]) {
    if (!discovery.IsMap() && !discovery.IsNull())
      yaml.fail(discovery, "mqtt.discovery must be a mapping, e.g. { prefix: homeassistant }");
    yaml.expect_keys(discovery, "mqtt.discovery", {"prefix"});
    MqttDiscoveryConfig d;
    if (discovery["prefix"]) d.prefix = yaml.text(discovery["prefix"]);
    if (d.prefix.empty() || d.prefix.front() == '/' || d.prefix.back() == '/' || d.prefix.find_first_of("#+") != std::string::npos)
      yaml.fail(discovery["prefix"] ? discovery["prefix"] : discovery,
                "mqtt.discovery.prefix must be a topic prefix without wildcards (# +) or a leading or trailing /");
    m.discovery = d;
  }
  parse_mqtt_buffer(state, node, m.buffer);
  state.config.mqtt = m;
}

void parse_sparkplug(ParseState& state, const YAML::Node& node) {
  const auto& yaml = state.yaml;
  yaml.expect_keys(node, "sparkplug", keys_with_broker({"client_id", "group_id", "edge_node_id", "primary_host", "commands"}));
  SparkplugConfig s;
  s.origin = yaml.position(node);
  parse_broker_connection(state, node, "sparkplug", s);
  if (!node["group_id"]) yaml.fail(node, "sparkplug needs 'group_id', the Sparkplug group of this edge node, e.g. plant-7");
  s.group_id = parse_sparkplug_id(yaml, node["group_id"], "group_id");
  if (node["edge_node_id"]) s.edge_node_id = parse_sparkplug_id(yaml, node["edge_node_id"], "edge_node_id");
  else s.edge_node_id = state.host.name.empty() || state.host.name.find_first_of("/#+") != std::string::npos
                            ? std::string("unima-bridge") : state.host.name;
  if (node["primary_host"]) s.primary_host = parse_sparkplug_id(yaml, node["primary_host"], "primary_host");
  s.client_id = parse_client_id(yaml, node, "sparkplug", fmt::format("unima-bridge-{}-{}", s.group_id, s.edge_node_id).substr(0, 64));
  if (node["commands"]) s.commands = yaml.boolean(node["commands"]);
  state.config.sparkplug = s;
}

}  // namespace unima::config::sections
