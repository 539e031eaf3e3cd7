#pragma once
// The RTU slave port (`modbus.rtu` in slave mode, SPEC §3) as a service, with the
// capture blocks it feeds (SPEC §4: what another master writes to, or reads from, a
// foreign slave goes to a user output). In master mode the line is the master's. The
// line is reopened on a reload only when its settings changed; opening never throws (a
// line that cannot be opened is retried), so nothing here can refuse a reload.

#include <memory>
#include <optional>
#include <span>

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
  std::unique_ptr<RtuSlavePort> make_port(const config::Config& config);
  SlaveContext context() const;
  void capture(std::span<const std::uint8_t> query, std::span<const std::uint8_t> response);

  Runtime& runtime_;
  std::unique_ptr<RtuSlavePort> port_;
  bool started_ = false;
  bool reopen_ = false;  // staged: the line's settings changed
};

/// The line an RTU slave serves in `config`: its slave line; none without one (in master
/// mode modbus.rtu is the master's).
std::optional<config::RtuConfig> slave_line(const config::Config& config);

}  // namespace unima::io
