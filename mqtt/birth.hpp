#pragma once
// `<prefix>/birth` (SPEC §15): what a fleet's inventory needs to know of a bridge the moment
// it connects — which version runs, with which config (its file's SHA-256, to compare with
// what the deployment tool sent), since when, on which machine, and whether its clock (the
// time of every document) is synchronised. Retained, so that the inventory learns it
// whenever it subscribes. Pure: the facts are handed in.
//
// A fleet that pushes configs from afar (SPEC §19) also learns from it where the config
// in force came from and how the last change ended, without asking each bridge.

#include <chrono>
#include <optional>
#include <string>

namespace unima::mqtt {

/// The config in force as the birth names it (remote::ConfigStatus, without the counters).
struct BirthConfig {
  std::string source = "file";            // file (the operator's), mqtt, http, cli
  std::optional<unsigned> number;         // the kept copy's; a file: none
  std::optional<std::string> by;          // who sent it; a file: none
  std::optional<std::string> applied_at;  // UTC; a file: none
  std::optional<std::string> last_result;  // of the last change since the start: applied, refused, rolled_back, busy
  std::optional<std::string> last_reason;
};

struct BirthFacts {
  std::string version;        // the daemon's
  std::string config_sha256;  // of the config file's bytes
  std::chrono::system_clock::time_point started;  // the daemon's start
  std::string hostname;
  std::string machine_id;     // the first 8 hex digits of /etc/machine-id (config/mqtt_identity.hpp); empty: none
  bool clock_synced = false;  // the kernel's NTP state
  BirthConfig config;
};

/// {"version":…,"config_sha256":…,"started":"<UTC>","hostname":…,"machine_id":…|null,"clock_synced":bool,
///  "config":{"source":…,"number":…|null,"by":…|null,"applied_at":…|null,"last_result":…|null,"last_reason":…|null}}
std::string birth_document(const BirthFacts& facts);

}  // namespace unima::mqtt
