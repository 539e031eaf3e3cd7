#pragma once
// The config as the Modbus master needs it (SPEC §4, docs/master.md): the active poll and
// send blocks resolved for the planner, and the timing of the line and of each device.

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "config/config.hpp"
#include "master/master_plan.hpp"
#include "master/master_scheduler.hpp"

namespace unima::config {

struct MasterSetup {
  std::vector<master::MasterBlock> blocks;               // active poll and send blocks, in config order
  std::vector<std::optional<banks::SourceRef>> sources;  // per block: what a send writes
  std::vector<Duration> stale_after;                     // per block: when a value goes stale
  master::PlanOptions plan;
  master::MasterScheduler::Options scheduler;
  std::map<std::uint8_t, master::MasterScheduler::DeviceTiming> devices;
  std::optional<modbus::RtuTiming> serial;            // the RTU line; nullopt for a TCP target
  bool operator==(const MasterSetup&) const = default;
};

/// Everything the master needs from `config` (which is in master mode).
/// `line`: the master line whose blocks, timing and devices it takes; null: the master
/// without a line (modbus.master.tcp). The overload without it takes the first master line.
MasterSetup master_setup(const Config& config, const LineConfig* line);
MasterSetup master_setup(const Config& config);

/// Everything a master port (io/master/master_port) is made of: its setup, its line or its
/// TCP target, its gateway and the line name its transactions carry.
struct MasterRecipe {
  MasterSetup setup;
  std::optional<RtuConfig> serial;  // the line; nullopt for modbus.master.tcp
  std::string tcp;                  // modbus.master.tcp as written, and parsed
  HostPort tcp_target;
  std::optional<GatewayConfig> gateway;
  std::string shown_name;           // ModbusConfig::shown_name of the line
  bool operator==(const MasterRecipe&) const = default;
};
MasterRecipe master_recipe(const Config& config, const LineConfig* line);

/// Whether a reload keeps the port made of `running` for `next` (SPEC §18: a line whose
/// keys are unchanged keeps its port, its queue and its counters). The positions in the
/// file are left out of the comparison: a line above that was added or removed moves them.
bool same_master_port(const MasterRecipe& running, const MasterRecipe& next);

/// The profile of each polled device: modbus.master.devices.N.profile, else the first
/// active block naming one.
struct DeviceProfileUse {
  const master::DeviceProfile* profile = nullptr;
  std::string origin;  // where the config names it
};
std::map<std::uint8_t, DeviceProfileUse> device_profiles(const Config& config);

/// What the devices' profiles say the config gets wrong (seeds 000–002, SPEC §9): a line
/// (baud, parity, stop bits) other than the device's, a response time-out below the time
/// the device takes to answer. Warnings, each with the file:line:col it is about.
std::vector<std::string> foreign_slave_warnings(const Config& config);

/// The requests of `setup`, merged (master::plan_requests) and phased
/// (master::assign_phases) for its line and devices.
std::vector<master::PlannedRequest> master_plan(const MasterSetup& setup);


}  // namespace unima::config
