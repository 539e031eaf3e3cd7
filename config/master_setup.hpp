#pragma once
// The config as the Modbus master needs it (SPEC §4, docs/master.md): the active poll and
// send blocks resolved for the planner, and the timing of the line and of each device.

#include <optional>
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
};

/// Everything the master needs from `config` (which is in master mode).
MasterSetup master_setup(const Config& config);

/// The requests of `setup`, merged (master::plan_requests) and phased
/// (master::assign_phases) for its line and devices.
std::vector<master::PlannedRequest> master_plan(const MasterSetup& setup);


}  // namespace unima::config
