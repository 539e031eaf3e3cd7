#pragma once
// The parsers of the config's sections (SPEC §7), one file per group of sections, walked in
// order by parse_text (config/loader.cpp). Each reads its YAML into the Config being built
// and fails with file:line:column through the YamlReader. None opens a file or looks at
// the host: what the host has comes in with Host, what is on disk is noted in
// Config::host_paths for check_on_host.

#include <yaml-cpp/yaml.h>

#include <string>
#include <utility>
#include <vector>

#include "banks/register_store.hpp"
#include "config/config.hpp"
#include "config/source_ref_parser.hpp"
#include "config/yaml_reader.hpp"

namespace unima::config::sections {

/// What the section parsers share while one document is parsed.
struct ParseState {
  ParseState(const std::string& origin, const Host& host, std::string in_place_of)
      : yaml(origin), host(host), in_place_of(std::move(in_place_of)) {
    config.file = origin;
  }

  YamlReader yaml;
  const Host& host;
  // The file the text stands for: defaults "beside the config" go beside it (the origin,
  // unless the text is a remote config kept elsewhere in the operator's file's place).
  std::string in_place_of;
  Config config;
  banks::BankShapes shapes{};  // once banks and devices are read: what mapping and blocks may name
  // modbus.tls.roles by name, resolved once the register map is known
  std::vector<std::pair<std::string, YAML::Node>> tls_roles;
};

// unimabus_sections.cpp: the UnimaBUS side and the files and socket the bridge keeps.
/// What is at `path` is looked at by check_on_host, not by the parse: it notes where the
/// file names it (`node`, or the section of a default).
void note_host_path(ParseState& state, HostPath::Use use, const YAML::Node& node, std::string key, std::string path);
void parse_unimabus(ParseState& state, const YAML::Node& node);
void parse_log(ParseState& state, const YAML::Node& node);
void parse_monitor(ParseState& state, const YAML::Node& node);
/// Also without the section (a null `node`): the default socket is where the daemon listens.
void parse_status(ParseState& state, const YAML::Node& node, const YAML::Node& root);
/// Where a file the daemon keeps across restarts goes by default: `name` in systemd's
/// $STATE_DIRECTORY when the service sets it, otherwise beside the config, `name` as its
/// extension (`bridge.yaml` -> `bridge.<name>`).
std::string default_state_path(const std::string& config_file, const Host& host, std::string_view name);
/// Also without the section: the default state file comes from the host's environment.
void parse_state(ParseState& state, const YAML::Node& node, const YAML::Node& root);

// modbus_section.cpp: modbus, its RTU line and the master's settings.
void parse_modbus(ParseState& state, const YAML::Node& node);
/// A device profile named in the config (modbus.master.devices.N.profile, a block's profile).
const master::DeviceProfile* parse_profile(const ParseState& state, const YAML::Node& node);
/// Unit ids of foreign slaves (modbus.gateway.units, a TLS role's "units 5-9"): `written`
/// is an id or a range "2-9", both ends within 1..247. An error, at `item`, begins with
/// `key` and shows `example` of the right form.
std::pair<std::uint8_t, std::uint8_t> parse_unit_range(const YamlReader& yaml, const YAML::Node& item,
                                                       std::string_view written, std::string_view key,
                                                       std::string_view example);

// network_sections.cpp: what listens on or connects to the network besides the feed.
TcpSlaveConfig parse_modbus_tcp(ParseState& state, const YAML::Node& node);
TlsSlaveConfig parse_modbus_tls(ParseState& state, const YAML::Node& node);
/// Addresses and CIDR ranges (modbus.tcp.allow, modbus.gateway.priority); `key` names it.
PeerAllowList parse_allow_list(const YamlReader& yaml, const YAML::Node& node, std::string_view key);
/// modbus.tls.roles' banks and registers, which must be served: after layout validation.
void resolve_tls_roles(ParseState& state);
void parse_http(ParseState& state, const YAML::Node& node);
void parse_mqtt(ParseState& state, const YAML::Node& node);
void parse_sparkplug(ParseState& state, const YAML::Node& node);

// report_section.cpp: deadbands and intervals (SPEC §21); after mqtt, whose period is
// max_interval's default, and after the devices its deadbands name.
void parse_report(ParseState& state, const YAML::Node& node);

// remote_config_section.cpp: who may change the config from afar (SPEC §19); after http
// and mqtt, which the channels it opens need.
void parse_remote_config(ParseState& state, const YAML::Node& node);

// layout_sections.cpp: where the banks are and what they hold.
void parse_bank_bases(ParseState& state, const YAML::Node& node);
void parse_devices(ParseState& state, const YAML::Node& node);
void parse_mapping(ParseState& state, const YAML::Node& node);
/// No two served windows overlap; the error names the one the file set, else `root`.
void validate_layout(const ParseState& state, const YAML::Node& root);
/// A source reference (`D1+0x21`, `X.0`) of a mapping entry or a block.
banks::SourceRef parse_source(const ParseState& state, const YAML::Node& node, SourceUse use);

// blocks_section.cpp: the function blocks.
void parse_blocks(ParseState& state, const YAML::Node& node);

}  // namespace unima::config::sections
