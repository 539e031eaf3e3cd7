#pragma once
// The UnimaBUS side of the status document — "unimabus" (the LED, the transport, the
// telegrams no bank took, the feed's clients), "devices" (D1..D4) and "modules" (S1..S7) —
// and their statistics. Filled by io/unimabus/unimabus_service.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "status/activity.hpp"
#include "status/statistic.hpp"

namespace unima::unimabus {

/// The UnimaBUS side as a whole; its JSON is the LED's keys and its own in one object.
struct UnimabusStatus {
  status::Activity led;  // after each telegram received
  std::string transport;                 // "feed", "sim", "replay"
  std::optional<std::string> recording;  // unimabus.record's file; none: not recording
  std::uint64_t telegrams_ignored = 0;   // for no configured D_N or S_N
  std::uint64_t telegrams_refused = 0;   // answered with an error
  std::optional<std::uint64_t> clients;  // the feed's connections; a transport without clients: left out
};
void to_json(nlohmann::json& j, const UnimabusStatus& s);
void from_json(const nlohmann::json& j, UnimabusStatus& s);

/// A device bank D_N.
struct DeviceStatus {
  std::string bank;                        // "D1".."D4"
  std::optional<std::string> type;         // its device table; none (null): D_N is not configured
  std::optional<std::uint64_t> address;    // its UnimaBUS address; left out when not configured
  bool online = false;
  std::optional<std::uint64_t> telegrams;  // taken into the bank; left out when not configured
};
void to_json(nlohmann::json& j, const DeviceStatus& s);
void from_json(const nlohmann::json& j, DeviceStatus& s);

/// An I/O module bank S_N.
struct ModuleStatus {
  std::string bank;  // "S1".."S7"
  std::uint64_t slot = 0;
  bool online = false;
  std::uint64_t telegrams = 0;  // taken into the bank
};
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE_WITH_DEFAULT(ModuleStatus, bank, slot, online, telegrams)

const std::vector<status::Statistic<UnimabusStatus>>& unimabus_statistics();
const std::vector<status::Statistic<DeviceStatus>>& device_statistics();
const std::vector<status::Statistic<ModuleStatus>>& module_statistics();

}  // namespace unima::unimabus
