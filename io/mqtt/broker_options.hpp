#pragma once
// How an MQTT client of the daemon reaches its broker, from the config section that names
// it — `mqtt` or `sparkplug`, whose broker, TLS and credential keys are the same
// (config/network_sections.cpp reads them alike): one place that turns them into
// MqttClientOptions and reads the password file.

#include <cerrno>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <string>
#include <string_view>

#include <fmt/format.h>

#include "io/mqtt/mqtt_client.hpp"

namespace unima::io {

/// The first line of a password file, without its line end; `section` names it in errors.
inline std::string password_of(const std::string& path, std::string_view section) {
  std::ifstream file(path);
  if (!file) throw std::runtime_error(fmt::format("{}.password_file {}: cannot be read: {}", section, path, std::strerror(errno)));
  std::string line;
  std::getline(file, line);
  if (!line.empty() && line.back() == '\r') line.pop_back();
  return line;
}

/// The options of `config`'s broker connection (status_topic and keepalive are left to
/// the caller).
template <typename Section>
MqttClientOptions broker_options(const Section& config, std::string_view section) {
  MqttClientOptions options;
  options.host = config.endpoint.host;
  options.port = config.endpoint.port;
  options.tls = config.tls;
  options.ca = config.ca;
  options.certificate = config.certificate;
  options.key = config.key;
  options.client_id = config.client_id;
  options.username = config.username;
  if (!config.password_file.empty()) options.password = password_of(config.password_file, section);
  options.version = config.version;
  return options;
}

}  // namespace unima::io
