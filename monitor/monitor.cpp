#include "monitor/monitor.hpp"

#include <spdlog/spdlog.h>

#include "monitor/monitor_sinks.hpp"
#include "modbus/adu_view.hpp"
#include "modbus/register_capture.hpp"

namespace unima::monitor {

Monitor::Monitor(const MonitorConfig& config)
    : config_(config), filter_(config.filter), indicators_(config.indicators),
      writer_(make_writer(config)) {}

std::unique_ptr<MonitorWriter> Monitor::make_writer(const MonitorConfig& config) {
  if (!config.enabled()) return nullptr;
  std::vector<std::unique_ptr<MonitorSink>> sinks;
  if (!config.file.empty()) sinks.push_back(std::make_unique<RotatingFileSink>(config.file, config.max_size, config.max_files));
  if (config.to_stdout) sinks.push_back(std::make_unique<StdoutSink>());
  MonitorWriter::Options options;
  options.format = config.format;
  options.capacity = config.queue;
  spdlog::info("monitor: logging to {}{}{} ({}, filter {})", config.file, !config.file.empty() && config.to_stdout ? " and " : "",
               config.to_stdout ? "stdout" : "", config.format == MonitorFormat::json ? "json" : "text",
               config.filter.describe());
  return std::make_unique<MonitorWriter>(std::move(sinks), options);
}

bool Monitor::same_log(const MonitorConfig& a, const MonitorConfig& b) {
  return a.file == b.file && a.to_stdout == b.to_stdout && a.format == b.format && a.max_size == b.max_size &&
         a.max_files == b.max_files && a.queue == b.queue;
}

void Monitor::reconfigure(const MonitorConfig& config, std::unique_ptr<MonitorWriter> writer) {
  if (!same_log(config_, config)) replace_writer(std::move(writer));
  if (writer_ && !(config.filter == filter_)) spdlog::info("monitor: filter {}", config.filter.describe());
  filter_ = config.filter;
  monitor::CaptureIndicators indicators(config.indicators);
  indicators.take_readings_from(indicators_);
  indicators_ = std::move(indicators);
  config_ = config;
}

// The old writer writes what it still holds before it goes; that may wait for the disk,
// which is acceptable once per reload.
void Monitor::replace_writer(std::unique_ptr<MonitorWriter> writer) {
  if (writer_) {
    writer_->stop();
    dropped_before_ += writer_->dropped();
    written_before_ += writer_->written();
  }
  writer_ = std::move(writer);
}

const modbus::TransactionCounters& Monitor::counters(modbus::PortKind port, std::string_view line) const {
  static const PortCounters none{};
  const auto index = static_cast<std::size_t>(port);
  if (line.empty()) return counters_[index];
  const auto found = line_counters_.find(line);
  return (found == line_counters_.end() ? none : found->second)[index];
}

Monitor::PortCounters& Monitor::counters_of(std::string_view line) {
  if (line.empty()) return counters_;
  if (const auto found = line_counters_.find(line); found != line_counters_.end()) return found->second;
  return line_counters_.emplace(std::string(line), PortCounters{}).first->second;
}

void Monitor::observe(const modbus::Transaction& t) {
  counters_of(t.line)[static_cast<std::size_t>(t.port)].count(t.state);
  if (t.answered_by_bridge) frame_sent(t.time);  // the port read the clock already
  if (!indicators_.empty())
    if (const auto captured = modbus::captured_registers(t)) indicators_.observe(*captured, t.time);
  const auto ix = next_ix_++;  // wraps 255 -> 0 (seed 004 §8)
  recent_.push(t, ix);
  if (!writer_) return;
  if (!filter_.passes_everything()) {
    const auto query = modbus::view_adu(t.query, modbus::framing_of(t));
    if (!filter_.matches(query.address, query.pdu)) return;
  }
  writer_->push(t, ix);
}

void Monitor::frame_sent(std::chrono::system_clock::time_point time) {
  last_frame_sent_ = time;
  ++frames_sent_;
}

}  // namespace unima::monitor
