#include "io/status_socket_service.hpp"

#include <spdlog/spdlog.h>

#include "config/socket_path.hpp"
#include "io/control_commands.hpp"

namespace unima::io {

StatusSocketService::StatusSocketService(Runtime& runtime)
    : runtime_(runtime), socket_(open(runtime.config().status.socket)) {}

std::unique_ptr<ControlSocket> StatusSocketService::open(const std::string& path) {
  try {
    return std::make_unique<ControlSocket>(
        runtime_.io, path,
        [this] { return nlohmann::json(runtime_.status()).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace); },
        [this](const ControlRequest& request, const ControlSocket::Reply& reply) {
          answer_control_request(runtime_.config_changes, request, reply);
        });
  } catch (const config::PathRefused&) {
    throw;
  } catch (const std::exception& e) {
    spdlog::warn("{}; `unima-bridge status` will not answer", e.what());
    return nullptr;
  }
}

void StatusSocketService::start() {
  if (socket_) socket_->start();
}

void StatusSocketService::stop() {
  if (socket_) socket_->stop();
}

void StatusSocketService::stage(const Banks& next) {
  if (next.config.status.socket != runtime_.config().status.socket || !socket_) staged_ = open(next.config.status.socket);
}

// Without a staged socket the running one stays, on a path that did not change or could
// not be taken.
void StatusSocketService::commit(const Banks&) {
  if (!staged_) return;
  stop();
  socket_ = std::move(staged_);
  start();
}

}  // namespace unima::io
