#pragma once
// A program the tests and benchmarks start beside themselves — the daemon, the CLI, the
// foreign-slave simulator, socat — and always end: the destructor stops and reaps it, so
// a failing test leaves no process behind. One fork/exec for all of them.

#include <sys/resource.h>
#include <sys/types.h>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace unima::test_support {

struct SpawnOptions {
  std::filesystem::path output;          // stdout and stderr go here (truncated); empty: /dev/null
  std::vector<std::string> environment;  // "NAME=value", added to or replacing the inherited ones
  rlim_t max_files = 0;                  // the child's RLIMIT_NOFILE; 0: inherited
  bool search_path = false;              // look the program up in PATH (socat)
  int stop_signal = SIGKILL;             // what the destructor sends
};

/// stdout and stderr to `output`, the rest as by default.
inline SpawnOptions writing_to(std::filesystem::path output) {
  SpawnOptions options;
  options.output = std::move(output);
  return options;
}

/// The same, ended with SIGTERM: for programs that clean up after themselves.
inline SpawnOptions stopped_by_sigterm(std::filesystem::path output) {
  auto options = writing_to(std::move(output));
  options.stop_signal = SIGTERM;
  return options;
}

class ChildProcess {
 public:
  /// Starts argv[0] with `argv`; throws std::runtime_error when it cannot fork. A program
  /// that cannot be executed exits 127.
  explicit ChildProcess(const std::vector<std::string>& argv, SpawnOptions options = {});
  ~ChildProcess();
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  pid_t pid() const { return pid_; }
  void signal(int signo) const;
  /// False once it has exited (and then it is reaped).
  bool running();
  /// Its exit status, or 128 + the signal that ended it; -1 when it had to be killed by
  /// stop(); nullopt while it runs.
  std::optional<int> exit_code() const { return exit_code_; }
  /// Sends `signo` and waits up to `timeout` for it to exit; kills it after that. How long
  /// it took, or nullopt when it had to be killed.
  std::optional<std::chrono::milliseconds> stop(int signo, std::chrono::milliseconds timeout);

 private:
  pid_t pid_ = -1;
  int stop_signal_ = SIGKILL;
  std::optional<int> exit_code_;
};

}  // namespace unima::test_support
