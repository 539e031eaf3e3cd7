#include "tests/integration/harness.hpp"

#include <signal.h>
#include <sys/resource.h>

#include <cerrno>
#include <cstring>
#include <system_error>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <thread>

namespace unima::test {

std::string next_line(const std::string& yaml) {
  return std::to_string(std::count(yaml.begin(), yaml.end(), '\n') + 1);
}

Daemon::Daemon(const TempDir& dir, const std::string& config_yaml, const std::vector<std::string>& environment)
    : config_path_(dir.path() / "bridge.yaml"), log_path_(dir.path() / "daemon.log") {
  rewrite_config(config_yaml);
  auto options = test_support::writing_to(log_path_);
  options.environment = environment;
  // UNIMA_TEST_BRIDGED runs the tests against another build of the daemon (an older
  // commit's, to see a new test fail where the defect it guards against still is).
  const char* other = std::getenv("UNIMA_TEST_BRIDGED");
  std::vector<std::string> argv{other && *other ? other : UNIMA_BRIDGED, "--config", config_path_.string()};
  for (const auto& v : environment) {  // the harness's own variables
    if (v.starts_with("UNIMA_TEST_MAX_FILES=")) options.max_files = std::stoul(v.substr(21));
    if (v.starts_with("UNIMA_TEST_STRACE=")) {  // the daemon's fdatasync and sendto calls, in order
      argv.insert(argv.begin(), {"strace", "-f", "-e", "trace=fdatasync,sendto", "-o", v.substr(18)});
      traced_ = true;
      options.search_path = true;
    }
  }
  process_ = std::make_unique<test_support::ChildProcess>(argv, std::move(options));
}

// Under strace the child is strace, which leaves the daemon running when it is killed:
// the daemon (strace's child) goes first.
Daemon::~Daemon() {
  if (!traced_ || !process_) return;
  std::ifstream children("/proc/" + std::to_string(process_->pid()) + "/task/" + std::to_string(process_->pid()) + "/children");
  for (pid_t child; children >> child;) ::kill(child, SIGKILL);
}

void Daemon::rewrite_config(const std::string& config_yaml) const {
  // Written beside and renamed, so that a reload never reads half a file.
  const auto tmp = config_path_.string() + ".tmp";
  std::ofstream(tmp) << config_yaml;
  std::filesystem::rename(tmp, config_path_);
}

void Daemon::signal(int signo) const { process_->signal(signo); }

void Daemon::limit_file_size(std::uint64_t bytes) const {
  const rlimit limit{static_cast<rlim_t>(bytes), RLIM_INFINITY};
  if (::prlimit(pid(), RLIMIT_FSIZE, &limit, nullptr) != 0)
    throw std::system_error(errno, std::generic_category(), "prlimit RLIMIT_FSIZE");
}

bool Daemon::running() { return process_->running(); }

std::optional<std::chrono::milliseconds> Daemon::terminate(std::chrono::milliseconds timeout) {
  return process_->stop(SIGTERM, timeout);
}

std::string Daemon::log() const {
  std::ifstream in(log_path_);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

std::size_t Daemon::log_count(const std::string& text) const {
  const auto all = log();
  std::size_t n = 0;
  for (auto at = all.find(text); at != std::string::npos; at = all.find(text, at + 1)) ++n;
  return n;
}

bool Daemon::logs_slowly(const std::string& text, std::string& report) const {
  report = log().substr(0, 2000);
  if (!wait_for_log(text)) return false;
  const auto before = log_count(text);
  std::this_thread::sleep_for(500ms);
  const auto more = log_count(text) - before;
  report = std::to_string(more) + " more '" + text + "' in 500 ms:\n" + log().substr(0, 2000);
  return more < 50;
}

bool Daemon::wait_for_log(const std::string& text, std::chrono::milliseconds timeout) const {
  return eventually([&] { return log().find(text) != std::string::npos; }, timeout);
}

std::unique_ptr<Daemon> start_with_few_descriptors(const TempDir& dir, const std::string& config_yaml,
                                                   std::uint16_t modbus_port, int max_files) {
  auto daemon = std::make_unique<Daemon>(dir, config_yaml,
                                         std::vector<std::string>{"UNIMA_TEST_MAX_FILES=" + std::to_string(max_files)});
  if (!wait_for_port(modbus_port)) throw std::runtime_error("the daemon does not listen:\n" + daemon->log());
  return daemon;
}

ResidentSet resident_set(pid_t pid) {
  ResidentSet set;
  std::ifstream status("/proc/" + std::to_string(pid) + "/status");
  std::string key;
  long value = 0;
  std::string unit;
  while (status >> key >> value >> unit) {
    if (key == "VmRSS:") set.now_kib = value;
    if (key == "VmHWM:") set.peak_kib = value;
    std::getline(status, unit);
  }
  return set;
}

std::vector<Socket> tcp_clients(std::uint16_t port, int count) {
  std::vector<Socket> clients;
  for (int i = 0; i < count; ++i) clients.push_back(Socket::tcp(port));
  return clients;
}

Bytes round_trip(std::uint16_t port, const Bytes& query) {
  auto socket = Socket::tcp(port);
  if (!socket.valid()) return {};
  socket.send(query);
  auto response = socket.receive(6);
  if (response.size() < 6) return response;
  const std::size_t length = static_cast<std::size_t>(response[4] << 8 | response[5]);
  const auto rest = socket.receive(length);
  response.insert(response.end(), rest.begin(), rest.end());
  return response;
}

}  // namespace unima::test
