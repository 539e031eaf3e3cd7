#include "tests/integration/harness.hpp"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <poll.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string_view>
#include <thread>

namespace unima::test {

namespace {
sockaddr_in loopback(std::uint16_t port) {
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(port);
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  return addr;
}
}  // namespace

std::string next_line(const std::string& yaml) {
  return std::to_string(std::count(yaml.begin(), yaml.end(), '\n') + 1);
}

CommandResult run(const std::string& command) {
  CommandResult result{-1, {}};
  FILE* pipe = ::popen((command + " 2>&1").c_str(), "r");
  char buf[4096];
  while (std::size_t n = std::fread(buf, 1, sizeof buf, pipe)) result.output.append(buf, n);
  const int status = ::pclose(pipe);
  result.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return result;
}

namespace {

bool bindable(std::uint16_t port) {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  auto addr = loopback(port);
  const bool ok = ::bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) == 0;
  ::close(fd);
  return ok;
}

// The first port the kernel hands out to connecting sockets (32768 by default).
std::uint16_t ephemeral_low() {
  std::ifstream range("/proc/sys/net/ipv4/ip_local_port_range");
  unsigned low = 0;
  return range >> low && low > 0 && low <= 65535 ? static_cast<std::uint16_t>(low) : 32768;
}

}  // namespace

// Below the ephemeral range: a port from bind(0) may become another test's client socket's
// local port before the daemon binds it ("Address already in use"); one down here stays
// free. Each test process starts at its own place in the range, so parallel tests rarely
// try the same port.
std::uint16_t free_port() {
  constexpr unsigned first = 10000;
  const unsigned low = ephemeral_low();
  if (low <= first + 1000) {  // an unusual range: fall back to the kernel's choice
    const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
    auto addr = loopback(0);
    if (::bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) throw std::runtime_error("bind");
    socklen_t len = sizeof addr;
    ::getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &len);
    ::close(fd);
    return ntohs(addr.sin_port);
  }
  const unsigned span = low - first;
  static unsigned next = static_cast<unsigned>(::getpid()) * 7919u % span;
  for (unsigned tries = 0; tries < span; ++tries) {
    const auto port = static_cast<std::uint16_t>(first + next++ % span);
    if (bindable(port)) return port;
  }
  throw std::runtime_error("no free loopback port below the ephemeral range");
}

long read_before(int fd, std::chrono::steady_clock::time_point deadline, std::span<std::uint8_t> buf) {
  const auto left = std::chrono::ceil<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
  pollfd p{fd, POLLIN, 0};
  if (::poll(&p, 1, static_cast<int>(std::max<long>(left.count(), 0))) <= 0) return 0;
  const auto got = ::read(fd, buf.data(), buf.size());
  return got > 0 ? static_cast<long>(got) : -1;
}

bool eventually(const std::function<bool()>& condition, std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (true) {
    if (condition()) return true;
    if (std::chrono::steady_clock::now() >= deadline) return false;
    std::this_thread::sleep_for(10ms);
  }
}

Daemon::Daemon(const TempDir& dir, const std::string& config_yaml, const std::vector<std::string>& environment)
    : config_path_(dir.path() / "bridge.yaml"), log_path_(dir.path() / "daemon.log") {
  rewrite_config(config_yaml);
  auto options = test_support::writing_to(log_path_);
  options.environment = environment;
  std::vector<std::string> argv{UNIMA_BRIDGED, "--config", config_path_.string()};
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

bool wait_for_port(std::uint16_t port, std::chrono::milliseconds timeout) {
  return eventually([&] { return Socket::tcp(port).valid(); }, timeout);
}

Socket Socket::tcp(std::uint16_t port) {
  const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  auto addr = loopback(port);
  if (::connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) {
    ::close(fd);
    return Socket(-1);
  }
  return Socket(fd);
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

Socket Socket::unix_socket(const std::string& path) {
  const int fd = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
  sockaddr_un addr{};
  addr.sun_family = AF_UNIX;
  std::strncpy(addr.sun_path, path.c_str(), sizeof addr.sun_path - 1);
  if (::connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) {
    ::close(fd);
    return Socket(-1);
  }
  return Socket(fd);
}

Socket::Socket(Socket&& other) noexcept : fd_(other.fd_), buffered_(std::move(other.buffered_)) { other.fd_ = -1; }

Socket::~Socket() { close(); }

void Socket::close() {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
}

void Socket::send(const Bytes& bytes) const {
  std::size_t sent = 0;
  while (sent < bytes.size()) {
    const auto n = ::send(fd_, bytes.data() + sent, bytes.size() - sent, MSG_NOSIGNAL);
    if (n <= 0) return;
    sent += static_cast<std::size_t>(n);
  }
}

void Socket::send(const std::string& text) const { send(Bytes(text.begin(), text.end())); }

Bytes Socket::receive(std::size_t n, std::chrono::milliseconds timeout) const {
  Bytes out;
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  std::uint8_t buf[4096];
  while (out.size() < n) {
    const auto got = read_before(fd_, deadline, std::span(buf, std::min(sizeof buf, n - out.size())));
    if (got <= 0) break;
    out.insert(out.end(), buf, buf + got);
  }
  return out;
}

bool Socket::closed_by_peer(std::chrono::milliseconds timeout) const {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  std::uint8_t buf[512];
  while (true) {
    const auto got = read_before(fd_, deadline, buf);
    if (got < 0) return true;  // EOF or reset
    if (got == 0 && std::chrono::steady_clock::now() >= deadline) return false;
  }
}

std::optional<std::string> Socket::read_line(std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  std::uint8_t buf[4096];
  while (true) {
    const auto newline = buffered_.find('\n');
    if (newline != std::string::npos) {
      auto line = buffered_.substr(0, newline);
      buffered_.erase(0, newline + 1);
      return line;
    }
    const auto got = read_before(fd_, deadline, buf);
    if (got <= 0) return std::nullopt;
    buffered_.append(reinterpret_cast<const char*>(buf), static_cast<std::size_t>(got));
  }
}

bool Socket::wait_for_line(const std::string& line, std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (true) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) return false;
    const auto got = read_line(left);
    if (!got) return false;
    if (*got == line) return true;
  }
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
