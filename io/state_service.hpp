#pragma once
// The state file as a service (SPEC §10): what it brought back goes into the banks before
// anything is served or published, its counters go into the status document, and a
// reload that names another file is told it takes effect at the next start.

#include "io/service.hpp"

namespace unima::io {

class StateService final : public Service {
 public:
  /// Puts the restored values into the running banks.
  explicit StateService(Runtime& runtime);

  void start() override {}
  void stop() override {}
  void stage(const Banks& next) override;
  void commit(const Banks&) override {}
  void describe(status::Document& status) const override;

 private:
  Runtime& runtime_;
};

}  // namespace unima::io
