#pragma once
// Integration-test harness: runs the built unima-bridged on a config written to a temp
// directory, and talks to it as real peers do (raw TCP, libmodbus, feed clients; the
// loopback sockets of tests/support/loopback, the peers of tests/support/peers). Every
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
#include "tests/support/eventually.hpp"
#include "tests/support/loopback.hpp"
#include "tests/support/shell_command.hpp"
#include "tests/support/temp_files.hpp"

namespace unima::test {

using namespace std::chrono_literals;
using test_support::Bytes;
using test_support::CommandResult;
using test_support::eventually;
using test_support::free_port;
using test_support::read_before;
using test_support::run;
using test_support::Socket;
using test_support::server_read_all;
using test_support::unread_by_server;
using test_support::wait_for_port;

/// The 1-based number of the line that text appended to `yaml` starts on.
std::string next_line(const std::string& yaml);

using test_support::read_file;

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
  /// The daemon may write no file past `bytes` (RLIM_INFINITY: any size): its soft
  /// RLIMIT_FSIZE, set with prlimit(2), so it can be raised again. Writes past it fail with
  /// EFBIG, as they would with ENOSPC on a full disk; its own log is held to it too.
  void limit_file_size(std::uint64_t bytes) const;
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
