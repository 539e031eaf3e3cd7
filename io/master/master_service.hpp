#pragma once
// The Modbus master (`modbus.mode: master`, SPEC §4, docs/master.md) as a service: its
// poll and send blocks read and write the running banks through hooks that look them up
// at each call, so they follow a reload. A reload opens the new config's line before
// anything is switched (a serial device may be missing) and swaps masters at commit.

#include <memory>

#include "io/master/master_port.hpp"
#include "io/service.hpp"

namespace unima::io {

class MasterService final : public Service {
 public:
  explicit MasterService(Runtime& runtime);
  ~MasterService() override { runtime_.gateway_line.attach(nullptr); }

  void start() override;
  void stop() override;
  void stage(const Banks& next) override;
  void abandon() override { next_.reset(); }
  void commit(const Banks& previous) override;
  void describe(status::Document& status) const override;

  const MasterPort* master() const { return master_.get(); }

 private:
  std::shared_ptr<MasterPort> make_master(const config::Config& config);

  Runtime& runtime_;
  std::shared_ptr<MasterPort> master_;
  std::shared_ptr<MasterPort> next_;  // staged
  bool started_ = false;
};

}  // namespace unima::io
