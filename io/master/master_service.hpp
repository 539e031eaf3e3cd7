#pragma once
// The Modbus master (`modbus.mode: master`, a `role: master` line; SPEC §4, §18,
// docs/master.md) as a service: a master per master line (or the one of
// modbus.master.tcp), whose poll and send blocks read and write the running banks through
// hooks that look them up at each call, so they follow a reload. The TCP and TLS ports'
// gateway requests reach the master of the line whose gateway routes their unit
// (io/gateway_line). A reload opens the new config's lines before anything is switched (a
// serial device may be missing) and swaps masters at commit.

#include <map>
#include <memory>
#include <string>

#include "io/master/master_port.hpp"
#include "io/service.hpp"

namespace unima::io {

class MasterService final : public Service {
 public:
  explicit MasterService(Runtime& runtime);
  ~MasterService() override;

  void start() override;
  void stop() override;
  void stage(const Banks& next) override;
  void abandon() override { next_.clear(); }
  void commit(const Banks& previous) override;
  void describe(status::Document& status) const override;

  /// The first master (by line name); null in slave mode.
  const MasterPort* master() const;

 private:
  using Masters = std::map<std::string, std::shared_ptr<MasterPort>>;  // by line name; "" for modbus.master.tcp
  std::shared_ptr<MasterPort> make_master(const config::Config& config, const config::LineConfig* line);
  Masters make_masters(const config::Config& config);
  void attach_gateways();

  Runtime& runtime_;
  Masters masters_;
  Masters next_;  // staged
  bool started_ = false;
};

}  // namespace unima::io
