#include "io/modbus/rtu_slave_service.hpp"

#include <algorithm>

#include <spdlog/spdlog.h>

#include "io/modbus/line_row.hpp"
#include "io/modbus/slave_context.hpp"
#include "modbus/capture.hpp"
#include "monitor/monitor_line.hpp"
#include "status/port_status.hpp"

namespace unima::io {

namespace {

bool same_serial(const config::RtuConfig& a, const config::RtuConfig& b) {
  return a.device == b.device && a.baud == b.baud && a.parity == b.parity && a.stop_bits == b.stop_bits &&
         a.rs485 == b.rs485 && a.low_latency == b.low_latency && a.frame_gap == b.frame_gap;
}

}  // namespace

RtuSlaveService::RtuSlaveService(Runtime& runtime) : runtime_(runtime) {
  for (const auto* line : runtime.config().modbus.lines_of(config::LineRole::slave))
    ports_.emplace(line->name, make_port(*line));
}

SlaveContext RtuSlaveService::context(const config::LineConfig& line) const {
  auto context = slave_context(runtime_);
  context.options.max_read_registers = modbus::max_read_registers_rtu;
  context.unit_id = line.address;  // the line's own (SPEC §18); modbus.address for modbus.rtu
  if (const auto name = runtime_.config().modbus.shown_name(line); !name.empty())
    context.on_transaction = [monitor = runtime_.monitor.get(), name = std::string(name)](modbus::Transaction t) {
      t.line = name;
      monitor->observe(t);
    };
  return context;
}

std::unique_ptr<RtuSlavePort> RtuSlaveService::make_port(const config::LineConfig& line) {
  auto port = std::make_unique<RtuSlavePort>(runtime_.io, line.serial, context(line));
  port->set_foreign_listener(
      [this, name = line.name](std::span<const std::uint8_t> query, std::span<const std::uint8_t> response) {
        capture(name, query, response);
      });
  return port;
}

// A write is taken from the master's request, a read from the foreign slave's response;
// only by the capture blocks of the line it was heard on.
void RtuSlaveService::capture(const std::string& line, std::span<const std::uint8_t> query,
                              std::span<const std::uint8_t> response) {
  const auto& by_line = runtime_.banks->capture_rules;
  const auto found = by_line.find(line);
  if (found == by_line.end() || found->second.empty()) return;
  const auto& rules = found->second;
  const auto captured =
      response.empty() ? modbus::captured_writes(rules, query) : modbus::captured_reads(rules, query, response);
  for (const auto& c : captured) {
    runtime_.banks->store->set_user_output(c.output, c.value);
    spdlog::debug("capture: user output {} = {} ({} of device {})", c.output, c.value,
                  c.via == modbus::Captured::Via::write ? "write" : "read", query[0]);
  }
}

void RtuSlaveService::start() {
  started_ = true;
  for (auto& [name, port] : ports_) port->start();
}

void RtuSlaveService::stop() {
  started_ = false;
  for (auto& [name, port] : ports_) port->stop();
}

void RtuSlaveService::stage(const Banks& next) {
  reopen_.clear();
  const auto coming = next.config.modbus.lines_of(config::LineRole::slave);
  for (const auto& [name, port] : ports_) {
    const auto same = std::find_if(coming.begin(), coming.end(), [&](const config::LineConfig* line) {
      return line->name == name && same_serial(line->serial, port->line());
    });
    if (same == coming.end()) reopen_.insert(name);
  }
}

void RtuSlaveService::commit(const Banks&) {
  for (const auto& name : reopen_) {
    ports_.at(name)->stop();
    ports_.erase(name);
  }
  reopen_.clear();
  for (const auto* line : runtime_.config().modbus.lines_of(config::LineRole::slave)) {
    if (const auto kept = ports_.find(line->name); kept != ports_.end()) {
      kept->second->set_context(context(*line));  // the new banks, address and monitor name
      continue;
    }
    auto& port = ports_[line->name] = make_port(*line);
    if (started_) port->start();
  }
}

// Each line's row always; its port's transactions once it has seen traffic.
void RtuSlaveService::describe(status::Document& status) const {
  const auto& served = runtime_.config().modbus;
  for (const auto* line : runtime_.config().modbus.lines_of(config::LineRole::slave)) {
    const auto port = ports_.find(line->name);
    if (port == ports_.end()) continue;
    if (!status.lines) status.lines.emplace();
    status.lines->push_back(line_row(*line, port->second->is_open(), port->second->counters(), port->second->queue_depth()));
    const auto shown = served.shown_name(*line);
    const auto& counters = runtime_.monitor->counters(modbus::PortKind::rtu, shown);
    if (counters.transactions == 0) continue;
    std::string name;
    monitor::append_port_name(name, modbus::PortKind::rtu, {}, shown);
    status.ports.push_back(status::port_status(name.c_str(), counters));
  }
}

}  // namespace unima::io
