#pragma once
// `<prefix>/birth` (SPEC §15): what a fleet's inventory needs to know of a bridge the moment
// it connects — which version runs, with which config (its file's SHA-256, to compare with
// what the deployment tool sent), since when, on which machine, and whether its clock (the
// time of every document) is synchronised. Retained, so that the inventory learns it
// whenever it subscribes. Pure: the facts are handed in.

#include <chrono>
#include <string>

namespace unima::mqtt {

struct BirthFacts {
  std::string version;        // the daemon's
  std::string config_sha256;  // of the config file's bytes
  std::chrono::system_clock::time_point started;  // the daemon's start
  std::string hostname;
  std::string machine_id;     // the first 8 hex digits of /etc/machine-id (config/mqtt_identity.hpp); empty: none
  bool clock_synced = false;  // the kernel's NTP state
};

/// {"version":…,"config_sha256":…,"started":"<UTC>","hostname":…,"machine_id":…|null,"clock_synced":bool}
std::string birth_document(const BirthFacts& facts);

}  // namespace unima::mqtt
