#pragma once
// The Modbus master (`modbus.mode: master`, a `role: master` line; SPEC §4, §18,
// docs/master.md) as a service: a master per master line (or the one of
// modbus.master.tcp), whose poll and send blocks read and write the running banks through
// hooks that look them up at each call, so they follow a reload. The TCP and TLS ports'
// gateway requests reach the master of the line whose gateway routes their unit
// (io/gateway_line). A reload keeps the master of a line whose keys, blocks and gateway are
// unchanged (config::same_master_port), with its port, queue and counters; it opens every
// other line of the new config before anything is switched (a serial device may be
// missing), and at commit stops the masters it replaces or removes and starts the new ones.

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
  struct Running {
    config::MasterRecipe recipe;
    std::shared_ptr<MasterPort> port;
  };
  using Masters = std::map<std::string, Running>;  // by line name; "" for modbus.master.tcp
  std::shared_ptr<MasterPort> make_master(const config::MasterRecipe& recipe);
  /// The masters of `config`; those whose recipe is one of `running`'s are taken from it.
  Masters make_masters(const config::Config& config, const Masters& running);
  void attach_gateways();

  Runtime& runtime_;
  Masters masters_;
  Masters next_;  // staged
  bool started_ = false;
};

}  // namespace unima::io
