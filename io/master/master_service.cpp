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

MasterService::MasterService(Runtime& runtime) : runtime_(runtime), master_(make_master(runtime.config())) {
  runtime_.gateway_line.attach(master_.get());
}

std::shared_ptr<MasterPort> MasterService::make_master(const config::Config& config) {
  if (config.modbus.mode != config::ModbusMode::master) return nullptr;
  MasterPort::Hooks hooks;
  hooks.read_source = [this](const banks::SourceRef& source) -> std::optional<std::uint16_t> {
    const auto value = runtime_.banks->store->read_source(source);
    if (!source.bit && value == banks::not_measured) return std::nullopt;
    return value;
  };
  hooks.set_output = [this](unsigned output, std::uint16_t value) { runtime_.banks->store->set_user_output(output, value); };
  hooks.on_fault = [this] { runtime_.error_hold.fault(); };
  const auto* line = config.modbus.line_of(config::LineRole::master);
  hooks.on_transaction = [this, name = std::string(line ? config.modbus.shown_name(*line) : std::string_view())](
                             modbus::Transaction t) {
    t.line = name;
    runtime_.monitor->observe(t);
    if (spdlog::should_log(spdlog::level::debug)) spdlog::debug("modbus master: {}", describe_master_transaction(t));
  };
  hooks.on_query_sent = [this](std::chrono::system_clock::time_point time) { runtime_.monitor->frame_sent(time); };
  return MasterPort::create(runtime_.io, config, std::move(hooks));
}

void MasterService::start() {
  started_ = true;
  if (master_) master_->start();
}

void MasterService::stop() {
  started_ = false;
  if (master_) master_->stop();
}

void MasterService::stage(const Banks& next) { next_ = make_master(next.config); }

void MasterService::commit(const Banks&) {
  if (master_) master_->stop();
  master_ = std::move(next_);
  runtime_.gateway_line.attach(master_.get());  // the ports' requests go to the new line
  if (master_ && started_) master_->start();
}

void MasterService::describe(status::Document& status) const {
  const auto& served = runtime_.config().modbus;
  const auto* line = served.line_of(config::LineRole::master);
  if (line && master_) {
    if (!status.lines) status.lines.emplace();
    status.lines->push_back(line_row(*line, true, master_->line_counters(), master_->queue_depth()));
  }
  const auto shown = line ? served.shown_name(*line) : std::string_view();
  const auto& counters = runtime_.monitor->counters(modbus::PortKind::master, shown);
  if (counters.transactions > 0) {
    std::string name;
    monitor::append_port_name(name, modbus::PortKind::master, {}, shown);
    status.ports.push_back(status::port_status(name.c_str(), counters));
  }
  if (!master_) return;
  std::vector<master::MasterDeviceStatus> devices;
  for (const auto& [device, c] : master_->counters())
    devices.push_back({device, c.requests, c.answered, c.timeouts, c.exceptions, c.bad_frames, c.retries});
  status.master = std::move(devices);
  if (const auto* gateway = runtime_.config().modbus.gateway()) status.gateway = gateway_status(*gateway, *master_);
}

}  // namespace unima::io
