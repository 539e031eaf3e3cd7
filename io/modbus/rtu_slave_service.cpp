#include "io/modbus/rtu_slave_service.hpp"

#include <spdlog/spdlog.h>

#include "io/modbus/line_row.hpp"
#include "io/modbus/slave_context.hpp"
#include "modbus/capture.hpp"
#include "monitor/monitor_line.hpp"
#include "status/port_status.hpp"

namespace unima::io {

namespace {

bool same_line(const std::optional<config::RtuConfig>& a, const std::optional<config::RtuConfig>& b) {
  if (a.has_value() != b.has_value()) return false;
  return !a || (a->device == b->device && a->baud == b->baud && a->parity == b->parity && a->stop_bits == b->stop_bits &&
                a->rs485 == b->rs485 && a->low_latency == b->low_latency && a->frame_gap == b->frame_gap);
}

}  // namespace

std::optional<config::RtuConfig> slave_line(const config::Config& config) {
  const auto* line = config.modbus.line_of(config::LineRole::slave);
  if (!line) return std::nullopt;
  return line->serial;
}

RtuSlaveService::RtuSlaveService(Runtime& runtime) : runtime_(runtime), port_(make_port(runtime.config())) {}

SlaveContext RtuSlaveService::context() const {
  auto context = slave_context(runtime_);
  context.options.max_read_registers = modbus::max_read_registers_rtu;
  const auto& served = runtime_.config().modbus;
  if (const auto* line = served.line_of(config::LineRole::slave)) {
    context.unit_id = line->address;  // the line's own (SPEC §18); modbus.address for modbus.rtu
    if (const auto name = served.shown_name(*line); !name.empty())
      context.on_transaction = [monitor = runtime_.monitor.get(), name = std::string(name)](modbus::Transaction t) {
        t.line = name;
        monitor->observe(t);
      };
  }
  return context;
}

std::unique_ptr<RtuSlavePort> RtuSlaveService::make_port(const config::Config& config) {
  const auto line = slave_line(config);
  if (!line) return nullptr;
  auto port = std::make_unique<RtuSlavePort>(runtime_.io, *line, context());
  port->set_foreign_listener(
      [this](std::span<const std::uint8_t> query, std::span<const std::uint8_t> response) { capture(query, response); });
  return port;
}

// A write is taken from the master's request, a read from the foreign slave's response.
void RtuSlaveService::capture(std::span<const std::uint8_t> query, std::span<const std::uint8_t> response) {
  const auto& rules = runtime_.banks->capture_rules;
  if (rules.empty()) return;
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
  if (port_) port_->start();
}

void RtuSlaveService::stop() {
  started_ = false;
  if (port_) port_->stop();
}

void RtuSlaveService::stage(const Banks& next) { reopen_ = !same_line(slave_line(runtime_.config()), slave_line(next.config)); }

void RtuSlaveService::commit(const Banks&) {
  if (!reopen_) {
    if (port_) port_->set_context(context());
    return;
  }
  reopen_ = false;
  if (port_) port_->stop();
  port_ = make_port(runtime_.config());
  if (port_ && started_) port_->start();
}

// The line's row always; its port's transactions once it has seen traffic.
void RtuSlaveService::describe(status::Document& status) const {
  const auto& served = runtime_.config().modbus;
  const auto* line = served.line_of(config::LineRole::slave);
  if (line && port_) {
    if (!status.lines) status.lines.emplace();
    status.lines->push_back(line_row(*line, port_->is_open(), port_->counters(), port_->queue_depth()));
  }
  const auto& counters = runtime_.monitor->counters(modbus::PortKind::rtu);
  if (counters.transactions == 0) return;
  std::string name;
  monitor::append_port_name(name, modbus::PortKind::rtu, {}, line ? served.shown_name(*line) : std::string_view());
  status.ports.push_back(status::port_status(name.c_str(), counters));
}

}  // namespace unima::io
