#include "app/config_in_force.hpp"

#include <exception>
#include <utility>

#include <spdlog/spdlog.h>

namespace unima::app {
namespace {

// The remote config in force, if it still may and can run: nullopt when the operator's
// file is (none in force, the file changed since, the text no longer loads).
std::optional<config::Config> remote_config_to_run(io::RemoteConfigStore& store, ConfigInForce& chosen,
                                                   const config::Host& host) {
  auto stored = store.in_force();
  if (!stored) return std::nullopt;
  if (stored->replaced_sha256 != chosen.operator_sha256) {
    spdlog::warn("remote config: {} changed since remote config {} was applied (by {}, at {}); the file is in force",
                 chosen.operator_file, stored->number, stored->by, stored->applied_at);
    try {
      store.put_file_in_force();
    } catch (const std::exception& e) {
      // The file runs all the same; the next start or SIGHUP finds it changed again.
      spdlog::error("remote config: cannot record that the file is in force: {}", e.what());
    }
    return std::nullopt;
  }
  try {
    // Its own path in its errors; its defaults beside the operator's file, as if it were it.
    auto config = config::load_text(store.text(*stored), stored->text_path.string(), host, chosen.operator_file);
    spdlog::info("remote config: remote config {} ({}, by {}, at {}) is in force in place of {}, which is unchanged",
                 stored->number, remote::source_name(stored->source), stored->by, stored->applied_at,
                 chosen.operator_file);
    chosen.remote = std::move(stored);
    return config;
  } catch (const std::exception& e) {
    spdlog::error("remote config: remote config {} no longer loads; the file {} is in force: {}", stored->number,
                  chosen.operator_file, e.what());
    return std::nullopt;
  }
}

ConfigInForce choose_config_in_force(const std::string& operator_path, config::Config operator_config,
                                    std::filesystem::path store_directory, const config::Host& host) {
  ConfigInForce chosen;
  chosen.operator_file = operator_path;
  chosen.operator_sha256 = operator_config.file_sha256;
  chosen.store_directory = std::move(store_directory);
  if (!chosen.store_directory.empty()) {
    io::RemoteConfigStore store(chosen.store_directory, io::RemoteConfigStore::default_keep);
    if (auto remote = remote_config_to_run(store, chosen, host)) {
      chosen.config = std::move(*remote);
      return chosen;
    }
  }
  // The operator's file runs: looked at on this host exactly as load_file would.
  config::check_on_host(operator_config);
  chosen.config = std::move(operator_config);
  return chosen;
}

}  // namespace

// The operator's file is parsed first in every case: its own errors stop the start or the
// reload as they always did, and its state file says where the store is.
ConfigInForce load_config_in_force(const std::string& operator_path, const config::Host& host) {
  auto operator_config = config::parse_text(config::read_config_file(operator_path), operator_path, host);
  auto directory = io::RemoteConfigStore::directory_for(operator_config);
  return choose_config_in_force(operator_path, std::move(operator_config), std::move(directory), host);
}

ConfigInForce load_config_in_force(const std::string& operator_path, const std::filesystem::path& store_directory,
                                   const config::Host& host) {
  auto operator_config = config::parse_text(config::read_config_file(operator_path), operator_path, host);
  return choose_config_in_force(operator_path, std::move(operator_config), store_directory, host);
}

}  // namespace unima::app
