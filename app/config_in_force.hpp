#pragma once
// Which config runs (SPEC §19, "Where it lives"): the operator's file, or the remote config
// kept in force in the store (io/remote_config_store) while the operator's file is the one
// it replaced, byte for byte. The daemon asks at start and on each SIGHUP; the operator's
// file is read each time and never written.

#include <filesystem>
#include <optional>
#include <string>

#include "config/config.hpp"
#include "io/remote_config_store.hpp"

namespace unima::app {

struct ConfigInForce {
  config::Config config;                  // what runs
  std::optional<io::StoredConfig> remote;  // nullopt: the operator's file
  std::string operator_file;
  std::string operator_sha256;            // of the operator's file's bytes now
  /// Where remote configs are kept: that of the operator's file's state file at start,
  /// fixed for the process (empty: `state.file: none`, nothing can be kept).
  std::filesystem::path store_directory;
};

/// The config to run at start and on SIGHUP: the remote config in force when the
/// operator's file is unchanged since it was applied, else the operator's file (when a
/// remote config was in force and the file changed: the store is told, and the log says
/// `remote config: <file> changed since remote config N was applied (by …, at …); the
/// file is in force`). A stored text that no longer loads: logged as an error naming its
/// path and position, and the file is in force (the store is not told: the next start or
/// SIGHUP tries it again). Throws as config::load_file for the operator's file's own
/// errors. The store is the one of the operator's file's state file
/// (io::RemoteConfigStore::directory_for).
ConfigInForce load_config_in_force(const std::string& operator_path,
                                   const config::Host& host = config::Host::this_machine());
/// The same with the store in `store_directory` (empty: none), as a running daemon keeps
/// it from its start: on SIGHUP, a state file the operator's file now names elsewhere
/// moves nothing before the next start (as for the state file itself).
ConfigInForce load_config_in_force(const std::string& operator_path, const std::filesystem::path& store_directory,
                                   const config::Host& host = config::Host::this_machine());

}  // namespace unima::app
