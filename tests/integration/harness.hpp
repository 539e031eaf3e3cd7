#pragma once
// Integration-test harness: runs the built unima-bridged on a config written to a temp
// directory, and talks to it as real peers do (raw TCP, libmodbus, feed clients). Every
// wait polls with a deadline; nothing sleeps a fixed time.

#include <sys/types.h>

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "tests/support/bridge_config.hpp"
#include "tests/support/child_process.hpp"
#include "tests/support/temp_files.hpp"

namespace unima::test {

using namespace std::chrono_literals;
using Bytes = std::vector<std::uint8_t>;

/// The 1-based number of the line that text appended to `yaml` starts on.
std::string next_line(const std::string& yaml);

struct CommandResult {
  int status;          // the exit code, -1 when killed
  std::string output;  // standard output and error together
};
/// Runs a shell command (the CLI under test) to its end.
CommandResult run(const std::string& command);

using test_support::read_file;

/// A loopback TCP port that was free a moment ago, below the kernel's ephemeral range.
std::uint16_t free_port();

/// Waits until `fd` (a socket or a pty) has something to read or `deadline` passes (it
/// looks at least once), then reads once into `buf`: the count read, 0 when nothing came
/// in time, -1 at end of stream or on an error.
long read_before(int fd, std::chrono::steady_clock::time_point deadline, std::span<std::uint8_t> buf);

/// Polls `condition` every 10 ms until it holds or `timeout` passes.
bool eventually(const std::function<bool()>& condition, std::chrono::milliseconds timeout = 5000ms);

using test_support::TempDir;

/// The daemon as a child process; killed when the object goes.
class Daemon {
 public:
  /// Writes `config_yaml` to DIR/bridge.yaml and starts unima-bridged on it; its stdout and
  /// stderr go to DIR/daemon.log. `environment` ("NAME=value") adds to the inherited one.
  /// `environment` adds variables; UNIMA_TEST_MAX_FILES=N instead limits its descriptors,
  /// UNIMA_TEST_STRACE=FILE runs it under strace, its fdatasync and sendto calls to FILE.
  Daemon(const TempDir& dir, const std::string& config_yaml, const std::vector<std::string>& environment = {});
  ~Daemon();

  void rewrite_config(const std::string& config_yaml) const;
  void signal(int signo) const;
  /// Sends SIGTERM; returns how long the daemon took to exit, or nullopt if it did not
  /// within `timeout` (it is then killed).
  std::optional<std::chrono::milliseconds> terminate(std::chrono::milliseconds timeout = 5000ms);
  bool running();
  std::optional<int> exit_code() const { return process_->exit_code(); }
  pid_t pid() const { return process_->pid(); }
  std::string log() const;
  bool wait_for_log(const std::string& text, std::chrono::milliseconds timeout = 5000ms) const;
  /// How many times `text` stands in the log so far.
  std::size_t log_count(const std::string& text) const;
  /// True when `text` appears in the log, then no more than a few times in the next
  /// 500 ms: a failing accept that waits before it retries logs about five, one that
  /// spins thousands. Otherwise false, with the start of the log in `report`.
  bool logs_slowly(const std::string& text, std::string& report) const;
  const std::filesystem::path& config_path() const { return config_path_; }

 private:
  std::filesystem::path config_path_;
  std::filesystem::path log_path_;
  std::unique_ptr<test_support::ChildProcess> process_;
  bool traced_ = false;  // started under strace (UNIMA_TEST_STRACE)
};

/// Waits until something accepts TCP connections on 127.0.0.1:port.
bool wait_for_port(std::uint16_t port, std::chrono::milliseconds timeout = 10000ms);

/// A blocking stream socket with receive deadlines.
class Socket {
 public:
  static Socket tcp(std::uint16_t port);  // 127.0.0.1
  static Socket unix_socket(const std::string& path);
  Socket(Socket&& other) noexcept;
  Socket& operator=(Socket&&) = delete;
  ~Socket();

  bool valid() const { return fd_ >= 0; }
  int fd() const { return fd_; }
  /// Closes it now (the destructor would later).
  void close();
  void send(const Bytes& bytes) const;
  void send(const std::string& text) const;
  /// Exactly n bytes, or fewer if the peer closed or the deadline passed.
  Bytes receive(std::size_t n, std::chrono::milliseconds timeout = 3000ms) const;
  /// True when the peer closed the connection within `timeout`.
  bool closed_by_peer(std::chrono::milliseconds timeout = 3000ms) const;
  /// One line without its "\n", or nullopt at the deadline or when closed.
  std::optional<std::string> read_line(std::chrono::milliseconds timeout = 3000ms);
  /// Reads lines until one equals `line`; false at the deadline.
  bool wait_for_line(const std::string& line, std::chrono::milliseconds timeout = 5000ms);

 private:
  explicit Socket(int fd) : fd_(fd) {}
  int fd_ = -1;
  std::string buffered_;
};

/// The daemon with room for only `max_files` descriptors (UNIMA_TEST_MAX_FILES), once it
/// listens on `modbus_port`: for the tests of what a port does when accept() fails.
/// Throws, with the daemon's log, when it does not listen.
std::unique_ptr<Daemon> start_with_few_descriptors(const TempDir& dir, const std::string& config_yaml,
                                                   std::uint16_t modbus_port, int max_files = 32);

/// A process's resident set now and at its peak (VmRSS, VmHWM of /proc/PID/status), in KiB.
struct ResidentSet {
  long now_kib = 0;
  long peak_kib = 0;
};
ResidentSet resident_set(pid_t pid);

/// UBSan's vptr check reads an object through a pipe(2): a daemon left with no descriptor
/// at all aborts at its next virtual call, a false report that cannot be suppressed (the
/// build does not recover from UBSan's findings). Tests that take every descriptor run in
/// the plain build only.
#ifdef UNIMA_SANITIZED
#define UNIMA_SKIP_WHEN_SANITIZED() GTEST_SKIP() << "takes every descriptor: UBSan's vptr check needs two"
#else
#define UNIMA_SKIP_WHEN_SANITIZED() (void)0
#endif

/// `count` TCP clients of 127.0.0.1:port; past the daemon's descriptors the listen backlog
/// takes them.
std::vector<Socket> tcp_clients(std::uint16_t port, int count);

/// A Modbus TCP query/response exchange on a fresh connection: the bytes as sent, the
/// response as received (MBAP + PDU; the MBAP length says how many to wait for).
Bytes round_trip(std::uint16_t port, const Bytes& query);

using test_support::BridgeConfig;

}  // namespace unima::test
