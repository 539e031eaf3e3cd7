#include "io/control_commands.hpp"

#include <pwd.h>
#include <unistd.h>

#include <array>

#include <spdlog/spdlog.h>

namespace unima::io {

namespace {

// "alice", or "uid 1001" for a user the system does not name.
std::string user_name(unsigned uid) {
  passwd entry{};
  passwd* found = nullptr;
  std::array<char, 4096> buffer{};
  if (::getpwuid_r(uid, &entry, buffer.data(), buffer.size(), &found) == 0 && found) return found->pw_name;
  return "uid " + std::to_string(uid);
}

bool may_change(unsigned uid) { return uid == 0 || uid == ::geteuid(); }

std::string error(const std::string& message) { return nlohmann::json{{"error", message}}.dump(); }

}  // namespace

void answer_control_request(ConfigChanges* changes, const ControlRequest& request, const ControlSocket::Reply& reply) {
  const auto json = nlohmann::json::parse(request.line, nullptr, false);
  if (!json.is_object() || !json.contains("command") || !json["command"].is_string())
    return reply(error(R"(a request is one JSON object per line with a "command")"));
  const auto command = json["command"].get<std::string>();
  if (!changes) return reply(error("this daemon takes no config changes"));
  const auto by = user_name(request.uid);
  const auto answer = [reply](const remote::ChangeAnswer& a) { reply(remote::answer_json(a)); };
  if (command == "config history") return reply(changes->history().dump(-1, ' ', false, nlohmann::json::error_handler_t::replace));
  if (command != "config show" && command != "config apply" && command != "config revert")
    return reply(error("unknown command '" + command + "'"));
  if (!may_change(request.uid)) {
    spdlog::warn("control: {} (pid {}) may not '{}': only root and the daemon's user may", by, request.pid, command);
    return reply(error(by + " may not '" + command + "': only root and the daemon's own user may"));
  }
  if (command == "config show") return reply(changes->in_force(true).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace));
  if (command == "config revert") return changes->revert(remote::Source::cli, by, answer);
  if (!json.contains("text") || !json["text"].is_string()) return reply(error("config apply needs the config's \"text\""));
  changes->apply(json["text"].get<std::string>(), remote::Source::cli, by, answer);
}

}  // namespace unima::io
