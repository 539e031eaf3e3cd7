// The core of the config's parse: it walks the document's sections in the order they
// depend on one another (banks and devices before what maps them; modbus before the blocks
// that name its devices; everything before the layout check and the TLS roles that name
// served registers). The sections themselves are in config/*_section*.cpp.

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>

#include <fmt/format.h>

#include "banks/yaml_document.hpp"
#include "config/config.hpp"
#include "config/section_parsers.hpp"
#include "tls/sha256.hpp"

namespace unima::config {

namespace {

Config parse_document(const YAML::Node& root, const std::string& origin, const Host& host,
                      const std::string& in_place_of) {
  using namespace sections;
  ParseState state(origin, host, in_place_of);
  auto& yaml = state.yaml;
  if (!root.IsNull() && !root.IsMap()) yaml.fail(root, "the config must be a mapping of sections");
  yaml.expect_keys(root, "the config",
                   {"unimabus", "modbus", "banks", "devices", "mapping", "blocks", "log", "monitor", "status", "state",
                    "http", "mqtt", "sparkplug", "report", "remote_config"});
  for (banks::BankId bank : banks::all_banks) state.config.bank_bases[index_of(bank)] = banks::default_base(bank);
  if (root["unimabus"]) parse_unimabus(state, root["unimabus"]);
  if (root["modbus"]) parse_modbus(state, root["modbus"]);
  if (root["banks"]) parse_bank_bases(state, root["banks"]);
  if (root["devices"]) parse_devices(state, root["devices"]);
  state.shapes = bank_shapes(state.config);
  if (root["mapping"]) parse_mapping(state, root["mapping"]);
  if (root["blocks"]) parse_blocks(state, root["blocks"]);
  if (root["log"]) parse_log(state, root["log"]);
  if (root["monitor"]) parse_monitor(state, root["monitor"]);
  parse_status(state, root["status"], root);
  parse_state(state, root["state"], root);
  if (root["http"]) parse_http(state, root["http"]);
  if (root["mqtt"]) parse_mqtt(state, root["mqtt"]);
  if (root["sparkplug"]) parse_sparkplug(state, root["sparkplug"]);
  // After mqtt: max_interval defaults to its period.
  if (root["report"]) parse_report(state, root["report"]);
  // After http and mqtt: the channels it opens need them.
  if (root["remote_config"]) parse_remote_config(state, root["remote_config"]);
  validate_layout(state, root);
  resolve_tls_roles(state);
  state.config.noted_warnings = yaml.take_warnings();
  return std::move(state.config);
}

}  // namespace

Config parse_text(const std::string& text, const std::string& origin, const Host& host) {
  return parse_text(text, origin, host, origin);
}

Config parse_text(const std::string& text, const std::string& origin, const Host& host, const std::string& in_place_of) {
  auto config = banks::read_yaml_document<ConfigError>(
      text, origin, [&](const YAML::Node& root) { return parse_document(root, origin, host, in_place_of); });
  config.file_sha256 = tls::sha256_hex(text);
  return config;
}

Config load_text(const std::string& text, const std::string& origin, const Host& host) {
  return load_text(text, origin, host, origin);
}

Config load_text(const std::string& text, const std::string& origin, const Host& host, const std::string& in_place_of) {
  auto config = parse_text(text, origin, host, in_place_of);
  check_on_host(config);
  return config;
}

std::string read_config_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ConfigError(fmt::format("{}: cannot open the config file: {}", path, std::strerror(errno)));
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

Config load_file(const std::string& path, const Host& host) { return load_text(read_config_file(path), path, host); }

}  // namespace unima::config
