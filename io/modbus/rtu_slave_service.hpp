#pragma once
// The RTU slave lines (`modbus.rtu` in slave mode, each `role: slave` line of
// modbus.lines; SPEC §3, §18) as a service: a port per line, each with its own address,
// its own capture blocks (SPEC §4: what another master writes to, or reads from, a foreign
// slave goes to a user output) and its own counters. A reload reopens only the lines whose
// settings changed and closes the lines that went: a line whose keys are unchanged keeps
// its port, its queue and its counters. Opening never throws (a line that cannot be opened
// is retried), so nothing here can refuse a reload.

#include <map>
#include <memory>
#include <set>
#include <span>
#include <string>

#include "io/modbus/rtu_slave_port.hpp"
#include "io/service.hpp"

namespace unima::io {

class RtuSlaveService final : public Service {
 public:
  explicit RtuSlaveService(Runtime& runtime);

  void start() override;
  void stop() override;
  void stage(const Banks& next) override;
  void commit(const Banks& previous) override;
  void describe(status::Document& status) const override;

 private:
  std::unique_ptr<RtuSlavePort> make_port(const config::LineConfig& line);
  SlaveContext context(const config::LineConfig& line) const;
  void capture(const std::string& line, std::span<const std::uint8_t> query, std::span<const std::uint8_t> response);

  Runtime& runtime_;
  std::map<std::string, std::unique_ptr<RtuSlavePort>> ports_;  // by line name
  bool started_ = false;
  std::set<std::string> reopen_;  // staged: the lines whose settings changed, or that went
};

}  // namespace unima::io
