// remote_config (SPEC §19): which channels may change the config in force from afar, and
// how a change is probed and kept. What a channel needs must be in the same file (an
// `mqtt` section for `mqtt: true`, `http.users` for the HTTP users), so that a config
// never names a way in that it does not open. Whether each HTTP user is in the users file
// is check/'s question: the parse reads no file.

#include <algorithm>
#include <chrono>
#include <limits>

#include <fmt/format.h>

#include "config/endpoint.hpp"
#include "config/section_parsers.hpp"

namespace unima::config::sections {

namespace {

constexpr Duration shortest_probe = std::chrono::seconds(1);
constexpr Duration longest_probe = std::chrono::minutes(10);
constexpr unsigned most_kept = 1000;

// remote_config.http: user names of http.users, each once.
std::vector<std::string> parse_remote_users(const ParseState& state, const YAML::Node& node) {
  const auto& yaml = state.yaml;
  if (!node.IsSequence())
    yaml.fail(node, "remote_config.http must be a list of user names of http.users, e.g. [alice]");
  std::vector<std::string> users;
  for (const auto& item : node) {
    auto user = yaml.text(item);
    if (user.empty() || user.find(':') != std::string::npos)
      yaml.fail(item, "remote_config.http: a user name is not empty and has no ':' (as in http.users)");
    if (std::find(users.begin(), users.end(), user) != users.end())
      yaml.fail(item, fmt::format("remote_config.http: '{}' is listed twice", user));
    users.push_back(std::move(user));
  }
  if (users.empty()) return users;
  const auto& http = state.config.http;
  if (!http)
    yaml.fail(node, "remote_config.http names users who may PUT /api/config, but there is no http section: add http "
                    "with tls and users, or take remote_config.http out");
  if (http->users.empty())
    yaml.fail(node, "remote_config.http names users who may PUT /api/config, but http has no users file: set "
                    "http.users, or take remote_config.http out");
  // Allowed (a site may mean to open TLS later), but no PUT will pass: say so now.
  if (!http->tls && !is_loopback_address(http->listen))
    yaml.warn(node, fmt::format("remote_config.http: http listens on {} without tls, and a PUT /api/config over plain "
                                "HTTP is refused from anywhere but loopback; set http.tls for these users to change "
                                "the config from afar",
                                http->listen));
  return users;
}

}  // namespace

void parse_remote_config(ParseState& state, const YAML::Node& node) {
  const auto& yaml = state.yaml;
  yaml.expect_keys(node, "remote_config", {"mqtt", "http", "probe", "keep"});
  RemoteConfig r;
  r.origin = yaml.position(node);
  r.http_origin = r.origin;
  if (const auto mqtt = node["mqtt"]) {
    r.mqtt = yaml.boolean(mqtt);
    if (r.mqtt && !state.config.mqtt)
      yaml.fail(mqtt, "remote_config.mqtt: true takes configs on <mqtt.topic>/config/set, but there is no mqtt "
                      "section: add mqtt, or set remote_config.mqtt to false");
  }
  if (const auto http = node["http"]) {
    r.http_origin = yaml.position(http);
    r.http = parse_remote_users(state, http);
  }
  if (const auto probe = node["probe"]) {
    r.probe = yaml.duration(probe);
    if (r.probe < shortest_probe || r.probe > longest_probe)
      yaml.fail(probe, fmt::format("remote_config.probe must be 1s..10m (written: {})", yaml.text(probe)));
  }
  if (const auto keep = node["keep"]) {
    const auto kept = yaml.number(keep, 0, std::numeric_limits<unsigned long>::max());
    if (kept < 1 || kept > most_kept)
      yaml.fail(keep, fmt::format("remote_config.keep must be 1..{} (applied configs kept in the state directory)",
                                  most_kept));
    r.keep = static_cast<unsigned>(kept);
  }
  state.config.remote_config = std::move(r);
}

}  // namespace unima::config::sections
