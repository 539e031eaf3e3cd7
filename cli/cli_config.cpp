#include "cli/cli_config.hpp"

#include <cstdio>
#include <fstream>
#include <optional>
#include <sstream>
#include <thread>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "cli/control_client.hpp"

namespace unima::cli {

namespace {

constexpr const char* config_usage =
    "usage: unima-bridge config apply FILE | show | history | revert [--json] [--timeout S] [--socket PATH | --config FILE]\n"
    "\n"
    "  apply FILE   check FILE as `check` does, apply it as a reload, and keep it once its\n"
    "               probe passed (remote_config.probe); else the daemon goes back to the\n"
    "               config before. Waits for the answer: applied (exit 0), refused,\n"
    "               rolled_back or busy (exit 1). The operator's file is never written.\n"
    "  show         the config in force, its source and sha256 (on standard error) and\n"
    "               its text (on standard output)\n"
    "  history      the configs applied from afar that the daemon keeps, newest first\n"
    "  revert       back to the operator's file, through the same check and probe\n"
    "  --json       the daemon's JSON answer\n"
    "  --timeout S  how long apply and revert wait for the answer (default 660 s: the\n"
    "               longest probe and a margin)\n"
    "  --config FILE, --socket PATH  which daemon, as for `status`\n"
    "  apply, show and revert need root or the daemon's own user.\n";

constexpr auto quick_timeout = std::chrono::seconds(10);

std::optional<std::string> read_file(const std::string& path, std::string& error) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    error = fmt::format("cannot open {}", path);
    return std::nullopt;
  }
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// The request's answer. A daemon that took the request for a status reader (the client
// was slower than the socket's grace) sends its status document: asked again.
ControlAnswer ask(const std::string& socket, const nlohmann::json& request, std::chrono::milliseconds timeout) {
  ControlAnswer answer;
  for (int attempt = 0; attempt < 5; ++attempt) {
    answer = ask_control(socket, request.dump(), timeout);
    if (!answer.text) return answer;
    const auto json = nlohmann::json::parse(*answer.text, nullptr, false);
    if (!(json.is_object() && json.contains("pid") && json.contains("ports"))) return answer;
  }
  answer.text.reset();
  answer.error = "the daemon on " + socket + " answered with its status each time: does it take `config` requests?";
  return answer;
}

// An answer of the one flow, as a person reads it: positions as FILE:line:column, so an
// editor jumps there.
int print_change_answer(const nlohmann::json& answer, const std::string& file) {
  const auto result = answer.value("result", std::string("?"));
  const auto reason = answer.value("reason", std::string{});
  fmt::print("{}{}{}\n", result, reason.empty() ? "" : ": ", reason);
  if (const auto errors = answer.find("errors"); errors != answer.end() && errors->is_array()) {
    for (const auto& e : *errors) {
      const auto line = e.value("line", 0U);
      if (line == 0) fmt::print("{}\n", e.value("message", std::string{}));
      else fmt::print("{}:{}:{}: {}\n", file, line, e.value("column", 0U), e.value("message", std::string{}));
    }
  }
  if (result == "applied") fmt::print("sha256 {}\n", answer.value("id", std::string{}));
  return result == "applied" ? 0 : 1;
}

void print_history(const nlohmann::json& answer) {
  const auto& entries = answer["history"];
  if (entries.empty()) {
    fmt::print("no config from afar kept: the operator's file has always been in force\n");
    return;
  }
  fmt::print("{:>4}  {:<20}  {:<4}  {:<16}  {:<12}  {}\n", "no.", "applied at", "via", "by", "sha256", "");
  for (const auto& e : entries)
    fmt::print("{:>4}  {:<20}  {:<4}  {:<16}  {:<12}  {}\n", e.value("number", 0U), e.value("applied_at", std::string{}),
               e.value("source", std::string{}), e.value("by", std::string{}), e.value("id", std::string{}).substr(0, 12),
               e.value("in_force", false) ? "in force" : "");
}

}  // namespace

int config_command(const std::vector<std::string>& args) {
  std::string action, file, socket, config_path;
  bool json = false;
  auto timeout = std::chrono::milliseconds(std::chrono::seconds(660));
  for (std::size_t i = 0; i < args.size(); ++i) {
    const auto& arg = args[i];
    const bool has_value = i + 1 < args.size();
    if (arg == "--help" || arg == "-h") {
      std::fputs(config_usage, stdout);
      return 0;
    }
    if (arg == "--json") json = true;
    else if (arg == "--socket" && has_value) socket = args[++i];
    else if (arg == "--config" && has_value) config_path = args[++i];
    else if (arg == "--timeout" && has_value) {
      try {
        timeout = std::chrono::milliseconds(static_cast<long long>(std::stod(args[++i]) * 1000));
      } catch (const std::exception&) {
        std::fprintf(stderr, "unima-bridge config: --timeout takes seconds\n%s", config_usage);
        return 2;
      }
    } else if (action.empty() && !arg.starts_with("-")) action = arg;
    else if (action == "apply" && file.empty() && !arg.starts_with("-")) file = arg;
    else {
      std::fprintf(stderr, "unima-bridge config: unknown argument '%s'\n%s", arg.c_str(), config_usage);
      return 2;
    }
  }
  if (action != "apply" && action != "show" && action != "history" && action != "revert") {
    std::fprintf(stderr, "unima-bridge config: say apply FILE, show, history or revert\n%s", config_usage);
    return 2;
  }
  if ((action == "apply") != !file.empty()) {
    std::fprintf(stderr, "unima-bridge config: apply takes one FILE, the others none\n%s", config_usage);
    return 2;
  }
  if (!socket.empty() && !config_path.empty()) {
    std::fprintf(stderr, "unima-bridge config: give --socket or --config, not both\n%s", config_usage);
    return 2;
  }
  try {
    socket = control_socket_path(socket, config_path);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "unima-bridge config: %s\n", e.what());
    return 1;
  }
  nlohmann::json request = {{"command", "config " + action}};
  if (action == "apply") {
    std::string error;
    const auto text = read_file(file, error);
    if (!text) {
      std::fprintf(stderr, "unima-bridge config: %s\n", error.c_str());
      return 1;
    }
    request["text"] = *text;
  }
  const bool waits = action == "apply" || action == "revert";
  const auto answer = ask(socket, request, waits ? timeout : std::chrono::milliseconds(quick_timeout));
  if (!answer.text) {
    std::fprintf(stderr, "unima-bridge config: %s\n", answer.error.c_str());
    return 1;
  }
  const auto reply = nlohmann::json::parse(*answer.text, nullptr, false);
  if (!reply.is_object()) {
    std::fprintf(stderr, "unima-bridge config: the daemon on %s sent no JSON answer\n", socket.c_str());
    return 1;
  }
  if (const auto error = reply.find("error"); error != reply.end()) {
    std::fprintf(stderr, "unima-bridge config: %s\n", error->get<std::string>().c_str());
    return 1;
  }
  if (json) {
    fmt::print("{}\n", reply.dump(2));
    return waits ? (reply.value("result", std::string{}) == "applied" ? 0 : 1) : 0;
  }
  if (waits) return print_change_answer(reply, action == "apply" ? file : "the operator's file");
  if (action == "history") {
    print_history(reply);
    return 0;
  }
  // show: what it is on standard error, the text alone on standard output (to redirect).
  const auto source = reply.value("source", std::string("file"));
  if (source == "file")
    fmt::print(stderr, "# the operator's file {} (sha256 {})\n", reply.value("file", std::string{}),
               reply.value("sha256", std::string{}));
  else
    fmt::print(stderr, "# remote config {} from {} by {} at {} (sha256 {})\n", reply.value("number", 0U), source,
               reply.value("by", std::string{}), reply.value("applied_at", std::string{}), reply.value("sha256", std::string{}));
  if (reply.contains("text") && reply["text"].is_string()) fmt::print("{}", reply["text"].get<std::string>());
  else {
    std::fprintf(stderr, "unima-bridge config: %s\n", reply.value("text_error", std::string("no text")).c_str());
    return 1;
  }
  return 0;
}

}  // namespace unima::cli
