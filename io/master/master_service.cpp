#include "io/master/master_service.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "io/modbus/line_row.hpp"
#include "master/gateway_status.hpp"
#include "modbus/request_handler.hpp"
#include "monitor/monitor_line.hpp"
#include "platform/utc_time.hpp"
#include "status/port_status.hpp"

namespace unima::io {

namespace {

double milliseconds(master::WaitTime::Duration duration) {
  // To the microsecond: the JSON stays short, and a line's waits are milliseconds long.
  return static_cast<double>(std::chrono::duration_cast<std::chrono::microseconds>(duration).count()) / 1000.0;
}

master::GatewayUnitStatus gateway_unit_status(std::uint8_t unit, const GatewayUnitCounters& c, std::size_t queue_depth) {
  master::GatewayUnitStatus s{.unit = unit,
                              .state = c.answering.answering() ? "answering" : "not answering",
                              .since = {},
                              .requests = c.requests,
                              .answered = c.answered,
                              .exceptions = c.exceptions,
                              .timeouts = c.timeouts,
                              .bad_frames = c.bad_frames,
                              .busy = c.busy,
                              .cache_hits = c.cache_hits,
                              .queue_depth = queue_depth,
                              .wait_ms = {milliseconds(c.wait.last()), milliseconds(c.wait.mean()), milliseconds(c.wait.max()),
                                          c.wait.count(), milliseconds(c.wait.sum())}};
  if (const auto silent = c.answering.silent_since()) platform::append_utc_time(s.since.emplace(), *silent);
  return s;
}

// modbus.gateway as it runs, and each unit a client has asked for.
master::GatewayStatus gateway_status(const config::GatewayConfig& config, const MasterPort& master) {
  master::GatewayStatus gateway{.routes = config::unit_ranges_text(config),
                                .priority = {},
                                .wait_ms = config.wait.count(),
                                .timeout_ms = {},
                                .cache_ms = config.cache.count(),
                                .units = {}};
  for (const auto& range : config.priority.ranges) gateway.priority.push_back(range.text);
  if (config.timeout) gateway.timeout_ms = config.timeout->count();
  for (const auto& [unit, counters] : master.gateway_units())
    gateway.units.push_back(gateway_unit_status(unit, counters, master.queue_depth(unit)));
  return gateway;
}

}  // namespace

MasterService::MasterService(Runtime& runtime) : runtime_(runtime), masters_(make_masters(runtime.config(), {})) {
  attach_gateways();
}

MasterService::~MasterService() { runtime_.gateway_line.detach_all(); }

std::shared_ptr<MasterPort> MasterService::make_master(const config::MasterRecipe& recipe) {
  MasterPort::Hooks hooks;
  hooks.read_source = [this](const banks::SourceRef& source) -> std::optional<std::uint16_t> {
    const auto value = runtime_.banks->store->read_source(source);
    if (!source.bit && value == banks::not_measured) return std::nullopt;
    return value;
  };
  hooks.set_output = [this](unsigned output, std::uint16_t value) { runtime_.banks->store->set_user_output(output, value); };
  hooks.on_fault = [this] { runtime_.error_hold.fault(); };
  hooks.on_transaction = [this, name = recipe.shown_name](modbus::Transaction t) {
    t.line = name;
    runtime_.monitor->observe(t);
    if (spdlog::should_log(spdlog::level::debug)) spdlog::debug("modbus master: {}", describe_master_transaction(t));
  };
  hooks.on_query_sent = [this](std::chrono::system_clock::time_point time) { runtime_.monitor->frame_sent(time); };
  return MasterPort::create(runtime_.io, recipe, std::move(hooks));
}

// A master per master line; in master mode without one, the master of modbus.master.tcp.
MasterService::Masters MasterService::make_masters(const config::Config& config, const Masters& running) {
  Masters masters;
  if (config.modbus.mode != config::ModbusMode::master) return masters;
  const auto add = [&](const std::string& name, const config::LineConfig* line) {
    auto recipe = config::master_recipe(config, line);
    const auto same = running.find(name);
    if (same != running.end() && config::same_master_port(same->second.recipe, recipe)) {
      masters.emplace(name, Running{std::move(recipe), same->second.port});
      return;
    }
    auto port = make_master(recipe);
    masters.emplace(name, Running{std::move(recipe), std::move(port)});
  };
  const auto lines = config.modbus.lines_of(config::LineRole::master);
  if (lines.empty()) add(std::string(), nullptr);
  for (const auto* line : lines) add(line->name, line);
  return masters;
}

// The ports' requests go to the line whose gateway routes their unit.
void MasterService::attach_gateways() {
  runtime_.gateway_line.detach_all();
  for (const auto& [name, master] : masters_)
    if (const auto& gateway = master.port->gateway_config()) runtime_.gateway_line.attach(gateway->units, master.port.get());
}

void MasterService::start() {
  started_ = true;
  for (auto& [name, master] : masters_) master.port->start();
}

void MasterService::stop() {
  started_ = false;
  for (auto& [name, master] : masters_) master.port->stop();
}

// Every changed or added line of the new config opened before anything is switched: one
// that cannot be opened fails the reload and leaves the running masters as they are.
void MasterService::stage(const Banks& next) { next_ = make_masters(next.config, masters_); }

void MasterService::commit(const Banks&) {
  for (auto& [name, master] : masters_) {
    const auto kept = next_.find(name);
    if (kept != next_.end() && kept->second.port == master.port) {
      spdlog::info("modbus master: {} unchanged, kept with its queue and counters",
                   name.empty() ? std::string("modbus.master.tcp") : "line " + name);
      continue;
    }
    master.port->stop();
  }
  masters_ = std::move(next_);
  next_.clear();
  for (auto& [name, master] : masters_) master.port->take_positions(master.recipe.setup);
  attach_gateways();
  if (started_)
    for (auto& [name, master] : masters_) master.port->start();  // a kept one runs on
}

const MasterPort* MasterService::master() const { return masters_.empty() ? nullptr : masters_.begin()->second.port.get(); }

void MasterService::describe(status::Document& status) const {
  const auto& served = runtime_.config().modbus;
  std::optional<std::vector<master::MasterDeviceStatus>> devices;
  for (const auto& [name, running] : masters_) {
    const auto* master = running.port.get();
    const auto* line = name.empty() ? nullptr : served.find_line(name);
    if (line) {
      if (!status.lines) status.lines.emplace();
      status.lines->push_back(line_row(*line, master->line_open(), master->line_counters(), master->queue_depth()));
    }
    const auto shown = line ? served.shown_name(*line) : std::string_view();
    const auto& counters = runtime_.monitor->counters(modbus::PortKind::master, shown);
    if (counters.transactions > 0) {
      std::string port;
      monitor::append_port_name(port, modbus::PortKind::master, {}, shown);
      status.ports.push_back(status::port_status(port.c_str(), counters));
    }
    if (!devices) devices.emplace();
    for (const auto& [device, c] : master->counters())
      devices->push_back({device, c.requests, c.answered, c.timeouts, c.exceptions, c.bad_frames, c.retries});
    // The gateway part: every line's units, the first line's settings with every line's routes.
    if (const auto& gateway = master->gateway_config()) {
      auto part = gateway_status(*gateway, *master);
      if (!status.gateway) {
        status.gateway = std::move(part);
      } else {
        status.gateway->routes += ", " + part.routes;
        for (auto& unit : part.units) status.gateway->units.push_back(std::move(unit));
      }
    }
  }
  if (devices) status.master = std::move(*devices);
}

}  // namespace unima::io
