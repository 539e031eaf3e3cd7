#pragma once
// The monitor as a service (SPEC §5, §8): its log follows a reload (a new writer only when
// the log's file or format changed), and the status document gets the Modbus LED, the
// four capture indicators and the monitor's counters.

#include <memory>

#include "io/service.hpp"

namespace unima::io {

class MonitorService final : public Service {
 public:
  explicit MonitorService(Runtime& runtime) : runtime_(runtime) {}

  void start() override {}
  void stop() override {}
  void stage(const Banks& next) override;
  void abandon() override { writer_.reset(); }
  void commit(const Banks& previous) override;
  void describe(status::Document& status) const override;

 private:
  Runtime& runtime_;
  std::unique_ptr<monitor::MonitorWriter> writer_;  // staged: the next log, when it changed
};

}  // namespace unima::io
