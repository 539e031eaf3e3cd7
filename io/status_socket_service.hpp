#pragma once
// The status socket as a service (`unima-bridge status`). It is the operator's window,
// not part of the bridge's service: when it cannot listen (no /run/unima-bridge outside
// systemd, say) the bridge serves on, and a reload tries again. A path that names
// something else than a socket is refused like a bad config (SPEC §10).

#include <memory>

#include "io/control_socket.hpp"
#include "io/service.hpp"

namespace unima::io {

class StatusSocketService final : public Service {
 public:
  explicit StatusSocketService(Runtime& runtime);

  void start() override;
  void stop() override;
  void stage(const Banks& next) override;
  void abandon() override { staged_.reset(); }
  void commit(const Banks& previous) override;

 private:
  std::unique_ptr<ControlSocket> open(const std::string& path);

  Runtime& runtime_;
  std::unique_ptr<ControlSocket> socket_;
  std::unique_ptr<ControlSocket> staged_;  // when the path changed, or the running one had failed
};

}  // namespace unima::io
