#include "config/master_setup.hpp"

#include <algorithm>

#include <fmt/format.h>

namespace unima::config {

std::vector<master::PlannedRequest> master_plan(const MasterSetup& setup) {
  auto plan = master::plan_requests(setup.blocks, setup.plan);
  std::vector<std::chrono::microseconds> slots;
  for (const auto& r : plan)
    slots.push_back(master::transaction_estimate(r, setup.serial) +
                    std::chrono::duration_cast<std::chrono::microseconds>(setup.scheduler.frame_gap));
  std::map<std::uint8_t, std::chrono::microseconds> gaps;
  for (const auto& [device, timing] : setup.devices)
    gaps[device] = std::chrono::duration_cast<std::chrono::microseconds>(timing.min_gap);
  master::assign_phases(plan, slots, gaps);
  return plan;
}

std::map<std::uint8_t, DeviceProfileUse> device_profiles(const Config& config) {
  std::map<std::uint8_t, DeviceProfileUse> profiles;
  for (const auto& [address, device] : config.modbus.master.devices)
    if (device.profile) profiles[address] = {device.profile, device.origin};
  for (const Block* block : config.active_blocks())
    if ((block->type == Block::Type::poll || block->type == Block::Type::send) && block->profile &&
        !profiles.count(block->device))
      profiles[block->device] = {block->profile, block->origin};
  return profiles;
}

namespace {

// The master line a device is polled on: its first poll or send block's; null when none
// names a line (modbus.master.tcp).
const LineConfig* line_of_device(const Config& config, std::uint8_t address) {
  for (const Block* block : config.active_blocks())
    if ((block->type == Block::Type::poll || block->type == Block::Type::send) && block->device == address)
      return config.modbus.find_line(block->line);
  return config.modbus.line_of(LineRole::master);
}

}  // namespace

std::vector<std::string> foreign_slave_warnings(const Config& config) {
  std::vector<std::string> found;
  const auto& m = config.modbus.master;
  for (const auto& [address, use] : device_profiles(config)) {
    const auto* line = line_of_device(config, address);
    const auto& p = *use.profile;
    const auto device = m.devices.find(address);
    const auto* set = device != m.devices.end() && device->second.line ? &*device->second.line : nullptr;
    if (!set && !p.line) continue;  // nothing known to compare with
    const auto& wire = set ? *set : *p.line;  // the device's character format
    if (const auto* rtu = line ? &line->serial : nullptr;
        rtu && (rtu->baud != wire.baud || parity_letter(rtu->parity) != wire.parity || rtu->stop_bits != wire.stop_bits))
      found.push_back(warning_text(rtu->origin, fmt::format("{} is {} baud 8{}{}, but device {} ({} at {}) {} {} baud 8{}{}{}",
                                  line->key, rtu->baud, parity_letter(rtu->parity), rtu->stop_bits, address, p.id,
                                  use.origin, set ? "is set to" : "talks at", wire.baud, wire.parity, wire.stop_bits,
                                  set ? "" : fmt::format(" by default ({}); if it was set to the line's, say so in "
                                                         "modbus.master.devices.{}.line", p.source, address))));
    if (p.min_reply_time.count() == 0) continue;
    const bool own = device != m.devices.end() && device->second.response_timeout;
    const Duration timeout = own ? *device->second.response_timeout : m.response_timeout;
    if (timeout < p.min_reply_time)
      found.push_back(warning_text(own ? device->second.origin : (m.origin.empty() ? use.origin : m.origin),
                                   fmt::format("device {} is a {}, which takes at least {} ms to answer ({}), but its "
                                               "response time-out is {} ms: every request would time out", address,
                                  p.id, std::chrono::duration_cast<std::chrono::milliseconds>(p.min_reply_time).count(),
                                  p.source, timeout.count())));
  }
  return found;
}

MasterSetup master_setup(const Config& config) { return master_setup(config, config.modbus.line_of(LineRole::master)); }

MasterSetup master_setup(const Config& config, const LineConfig* line) {
  const auto& m = config.modbus.master;
  MasterSetup setup;
  std::map<std::uint8_t, const master::DeviceProfile*> profiles;
  for (const auto& [address, use] : device_profiles(config)) profiles[address] = use.profile;

  for (const Block* block : config.active_blocks()) {
    if (block->type != Block::Type::poll && block->type != Block::Type::send) continue;
    if (block->line != (line ? line->name : std::string())) continue;  // another line's
    master::MasterBlock b;
    b.kind = block->type == Block::Type::poll ? master::MasterBlock::Kind::poll : master::MasterBlock::Kind::send;
    b.device = block->device;
    b.function = block->function;
    b.reg = block->reg;
    b.count = block->extent();
    b.type = block->data_type;
    b.order = block->word_order;
    b.scale = block->scale;
    b.period = block->period;
    b.output = block->output;
    b.name = block->point.empty() ? fmt::format("0x{:04X}", block->reg) : block->point;
    b.origin = block->origin;
    setup.blocks.push_back(std::move(b));
    setup.sources.push_back(block->source);
    // Never shorter than two periods: a slow poll is not stale between two of its reads.
    setup.stale_after.push_back(std::max(m.stale_after, 2 * block->period));
  }

  setup.plan.merge_gap = m.merge_gap;
  setup.plan.max_read_registers = static_cast<std::uint16_t>(m.max_read_registers);

  auto& s = setup.scheduler;
  s.retries = m.retries;
  s.degrade_after = m.degrade_after;
  s.backoff = m.backoff;
  s.backoff_max = m.backoff_max;
  s.default_timing = {m.min_gap, m.response_timeout};
  if (line) {
    setup.serial = line_timing(line->serial);
    s.frame_gap = setup.serial->frame_gap;
    s.char_time = setup.serial->character;
    for (const auto& [address, profile] : profiles) s.frame_gap = std::max<master::MasterScheduler::Duration>(s.frame_gap, profile->frame_gap);
  }
  for (const auto& block : setup.blocks) {
    if (setup.devices.count(block.device)) continue;
    master::MasterScheduler::DeviceTiming timing{m.min_gap, m.response_timeout};
    if (const auto p = profiles.find(block.device); p != profiles.end()) timing.min_gap = p->second->min_gap;
    if (const auto d = m.devices.find(block.device); d != m.devices.end()) {
      if (d->second.min_gap) timing.min_gap = *d->second.min_gap;
      if (d->second.response_timeout) timing.response_timeout = *d->second.response_timeout;
    }
    setup.devices[block.device] = timing;
  }
  return setup;
}

MasterRecipe master_recipe(const Config& config, const LineConfig* line) {
  MasterRecipe recipe{.setup = master_setup(config, line),
                      .serial = {},
                      .tcp = {},
                      .tcp_target = {},
                      .gateway = {},
                      .shown_name = {}};
  if (line) {
    recipe.serial = line->serial;
    recipe.gateway = line->gateway;
    recipe.shown_name = config.modbus.shown_name(*line);
  } else {
    recipe.tcp = config.modbus.master.tcp;
    recipe.tcp_target = config.modbus.master.tcp_target;
  }
  return recipe;
}

namespace {

MasterRecipe without_positions(MasterRecipe recipe) {
  for (auto& block : recipe.setup.blocks) block.origin.clear();
  if (recipe.serial) recipe.serial->origin.clear();
  if (recipe.gateway) recipe.gateway->origin.clear();
  return recipe;
}

}  // namespace

bool same_master_port(const MasterRecipe& running, const MasterRecipe& next) {
  return without_positions(running) == without_positions(next);
}

}  // namespace unima::config
