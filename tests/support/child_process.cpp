#include "tests/support/child_process.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <stdexcept>
#include <string_view>
#include <thread>

extern char** environ;

namespace unima::test_support {

namespace {

std::vector<std::string> child_environment(const std::vector<std::string>& overrides) {
  const auto name_of = [](std::string_view variable) { return variable.substr(0, variable.find('=') + 1); };
  std::vector<std::string> variables;
  for (char** v = environ; *v != nullptr; ++v) {
    bool overridden = false;
    for (const auto& o : overrides) overridden = overridden || name_of(*v) == name_of(o);
    if (!overridden) variables.emplace_back(*v);
  }
  variables.insert(variables.end(), overrides.begin(), overrides.end());
  return variables;
}

std::vector<char*> pointers(std::vector<std::string>& strings) {
  std::vector<char*> out;
  for (auto& s : strings) out.push_back(s.data());
  out.push_back(nullptr);
  return out;
}

int exit_status(int status) { return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status); }

}  // namespace

ChildProcess::ChildProcess(const std::vector<std::string>& argv, SpawnOptions options)
    : stop_signal_(options.stop_signal) {
  // Everything is built before fork: the child only calls what is safe between fork and exec.
  auto args = argv;
  auto arg_pointers = pointers(args);
  auto variables = child_environment(options.environment);
  auto env_pointers = pointers(variables);
  const std::string output = options.output.empty() ? std::string("/dev/null") : options.output.string();
  const int flags = options.output.empty() ? O_WRONLY : O_WRONLY | O_CREAT | O_TRUNC;
  pid_ = ::fork();
  if (pid_ < 0) throw std::runtime_error("fork");
  if (pid_ == 0) {
    const int out = ::open(output.c_str(), flags, 0644);
    ::dup2(out, STDOUT_FILENO);
    ::dup2(out, STDERR_FILENO);
    if (options.max_files != 0) {
      const rlimit limit{options.max_files, options.max_files};
      ::setrlimit(RLIMIT_NOFILE, &limit);
    }
    if (options.search_path) ::execvpe(arg_pointers[0], arg_pointers.data(), env_pointers.data());
    else ::execve(arg_pointers[0], arg_pointers.data(), env_pointers.data());
    ::_exit(127);
  }
}

ChildProcess::~ChildProcess() {
  if (pid_ > 0 && !exit_code_) {
    ::kill(pid_, stop_signal_);
    ::waitpid(pid_, nullptr, 0);
  }
}

void ChildProcess::signal(int signo) const { ::kill(pid_, signo); }

bool ChildProcess::running() {
  if (exit_code_) return false;
  int status = 0;
  if (::waitpid(pid_, &status, WNOHANG) == pid_) {
    exit_code_ = exit_status(status);
    return false;
  }
  return true;
}

std::optional<std::chrono::milliseconds> ChildProcess::stop(int signo, std::chrono::milliseconds timeout) {
  const auto start = std::chrono::steady_clock::now();
  signal(signo);
  while (running()) {
    if (std::chrono::steady_clock::now() - start >= timeout) {
      ::kill(pid_, SIGKILL);
      ::waitpid(pid_, nullptr, 0);
      exit_code_ = -1;
      return std::nullopt;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::steady_clock::now() - start);
}

}  // namespace unima::test_support
