// What the config depends on from the machine it runs on: the host's name and environment,
// given to the parse (Host), and what is on disk where the config points, looked at once
// after the parse (check_on_host) by `unima-bridge check`, the daemon's start and a reload.

#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <fmt/format.h>

#include "config/config.hpp"
#include "config/socket_path.hpp"
#include "monitor/log_path.hpp"
#include "tls/pem_check.hpp"

namespace unima::config {

namespace {

std::string host_name() {
  char name[256] = {};
  if (::gethostname(name, sizeof name - 1) != 0) return {};
  return name;
}

// Read now, so that `check` and a reload see a bad line before anything starts (SPEC §6).
std::shared_ptr<const unimabus::Recording> read_recording(const ReplayConfig& replay) {
  std::ifstream in(replay.file, std::ios::binary);
  if (!in)
    throw ConfigError(
        fmt::format("{}: cannot read the recording {}: {}", replay.file_origin, replay.file, std::strerror(errno)));
  std::ostringstream text;
  text << in.rdbuf();
  try {
    return std::make_shared<const unimabus::Recording>(unimabus::parse_recording(text.str(), replay.file));
  } catch (const unimabus::RecordingError& e) {
    throw ConfigError(e.what());
  }
}

// The state file is read at start and rewritten beside itself: a FIFO would hang the
// start, a device or a directory cannot be renamed over (SPEC §10).
std::optional<std::string> refused_state_path(const std::string& path) {
  struct stat st{};
  if (::lstat(path.c_str(), &st) != 0 || S_ISREG(st.st_mode)) return std::nullopt;
  const char* what = S_ISLNK(st.st_mode)    ? "a symbolic link"
                     : S_ISFIFO(st.st_mode) ? "a FIFO"
                     : S_ISDIR(st.st_mode)  ? "a directory"
                     : S_ISSOCK(st.st_mode) ? "a socket"
                                            : "a device";
  return fmt::format("{} is {}, not a regular file; the state is kept in a file of its own", path, what);
}

// Read by the daemon at start, as whoever runs `check` reads it now.
std::optional<std::string> unreadable(const std::string& path) {
  std::ifstream file(path);
  if (file) return std::nullopt;
  const auto why = errno == ENOENT ? std::string("no such file: correct the path, or put the file there")
                                   : fmt::format("cannot be read: {}", std::strerror(errno));
  return fmt::format("{}: {}", path, why);
}

std::optional<tls::PemContent> pem_content(HostPath::Use use) {
  switch (use) {
    case HostPath::Use::certificate: return tls::PemContent::certificate;
    case HostPath::Use::private_key: return tls::PemContent::private_key;
    case HostPath::Use::ca_certificates: return tls::PemContent::ca_certificates;
    default: return std::nullopt;
  }
}

// Why the daemon will not use `path` as `use` says, or nullopt. A socket path is checked
// again right before the daemon removes anything (config/socket_path).
std::optional<std::string> refusal(const Config& config, const HostPath& path) {
  if (const auto content = pem_content(path.use)) {
    auto problem = tls::pem_file_problem(path.path, *content);
    for (const auto& certificate : config.host_paths)
      if (!problem && !path.certificate.empty() && certificate.key == path.certificate &&
          !tls::pem_file_problem(certificate.path, tls::PemContent::certificate))
        problem = tls::key_mismatch(certificate.path, path.path, certificate.key);
    if (problem) return fmt::format("{}: {}", path.path, *problem);
    return std::nullopt;
  }
  switch (path.use) {
    case HostPath::Use::unix_socket: return socket_path_conflict(path.path);
    case HostPath::Use::log_file: return monitor::refused_log_path(path.path);
    case HostPath::Use::state_file: return refused_state_path(path.path);
    case HostPath::Use::secret_file: return unreadable(path.path);
    default: return std::nullopt;
  }
}

// What the daemon copes with, but a technician should know of: a serial device that is
// not there (the daemon opens it when it comes), a certificate out of its validity, a
// file in a directory that is not there (the daemon makes it: a mistyped path?).
std::optional<std::string> doubt(const Config& config, const HostPath& path) {
  if (path.use == HostPath::Use::state_file || path.use == HostPath::Use::log_file) {
    const auto directory = std::filesystem::path(path.path).parent_path();
    std::error_code ignored;
    if (!directory.empty() && !std::filesystem::exists(directory, ignored))
      return fmt::format("the directory {} is not there; the daemon makes it at start: correct the path if it is mistyped",
                         directory.string());
    return std::nullopt;
  }
  if (path.use == HostPath::Use::certificate || path.use == HostPath::Use::ca_certificates)
    return tls::certificate_out_of_date(path.path, std::time(nullptr));
  if (path.use != HostPath::Use::serial_device || ::access(path.path.c_str(), R_OK | W_OK) == 0) return std::nullopt;
  const auto why = errno == ENOENT ? std::string("no such device") : std::string(std::strerror(errno));
  if (const auto* master = config.modbus.line_of(LineRole::master); master && master->serial.device == path.path)
    return fmt::format("{}; the master needs its line: the daemon will not start until it can open it", why);
  return fmt::format("{}; the daemon starts without it and tries to open it again every {} s (an adapter not plugged "
                     "in yet is fine)",
                     why, std::chrono::duration_cast<std::chrono::seconds>(serial_reopen_longest_delay).count());
}

}  // namespace

Host Host::this_machine(const std::string& machine_id_path) {
  Host host;
  host.name = host_name();
  std::ifstream machine_id(machine_id_path);
  std::string line;
  if (machine_id && std::getline(machine_id, line)) host.machine_id = machine_id_digits(line);
  host.environment = [](std::string_view variable) {
    const char* value = std::getenv(std::string(variable).c_str());
    return std::string(value ? value : "");
  };
  return host;
}

void check_on_host(Config& config) {
  if (auto& replay = config.unimabus.replay; config.unimabus.transport == TransportKind::replay)
    replay.recording = read_recording(replay);
  for (const auto& path : config.host_paths) {
    if (const auto refused = refusal(config, path))
      throw ConfigError(fmt::format("{}: {}: {}", path.origin, path.key, *refused));
    if (const auto doubted = doubt(config, path))
      config.noted_warnings.push_back(warning_text(path.origin, fmt::format("{}: {}: {}", path.key, path.path, *doubted)));
  }
}

}  // namespace unima::config
