// The daemon as systemd runs it: the sd_notify(3) protocol (READY, RELOADING, STOPPING,
// STATUS, WATCHDOG keep-alives) on a NOTIFY_SOCKET the test binds in systemd's place, and
// the sd-daemon(3) priority prefixes when stderr is the journal stream.

#include <poll.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <sstream>

#include "tests/integration/bridge_fixture.hpp"
#include "tests/support/peers/notify_socket.hpp"

namespace unima::test {
namespace {

using test_support::NotifySocket;

class UnderSystemd : public BridgeTest {
 protected:
  void start_with(const std::vector<std::string>& environment) {
    daemon = std::make_unique<Daemon>(dir, config.yaml(), environment);
  }
  NotifySocket notify{dir.path() / "notify"};
};

TEST_F(UnderSystemd, ReadyIsSentOnceThePortsServe) {
  start_with({notify.environment()});
  const auto ready = notify.wait_for("READY=1");
  ASSERT_TRUE(ready) << daemon->log();
  EXPECT_TRUE(Socket::tcp(config.modbus_port).valid());  // no waiting: READY means serving
  EXPECT_TRUE(Socket::tcp(config.feed_port).valid());
  EXPECT_TRUE(NotifySocket::carries(*ready, "STATUS=running; config " + daemon->config_path().string())) << *ready;
}

TEST_F(UnderSystemd, AReloadIsBracketedByReloadingAndReady) {
  start_with({notify.environment()});
  ASSERT_TRUE(notify.wait_for("READY=1")) << daemon->log();
  daemon->signal(SIGHUP);
  ASSERT_TRUE(notify.wait_for("RELOADING=1")) << daemon->log();
  const auto ready = notify.wait_for("READY=1");
  ASSERT_TRUE(ready) << daemon->log();
  EXPECT_TRUE(NotifySocket::carries(*ready, "STATUS=running; reloaded " + daemon->config_path().string())) << *ready;
}

TEST_F(UnderSystemd, AFailedReloadSaysSoInTheStatus) {
  start_with({notify.environment()});
  ASSERT_TRUE(notify.wait_for("READY=1")) << daemon->log();
  daemon->rewrite_config(config.yaml() + "modbus_typo: 1\n");
  daemon->signal(SIGHUP);
  ASSERT_TRUE(notify.wait_for("RELOADING=1")) << daemon->log();
  const auto ready = notify.wait_for("READY=1");
  ASSERT_TRUE(ready) << daemon->log();
  EXPECT_NE(ready->find("STATUS=reload failed, running the previous config: "), std::string::npos) << *ready;
  EXPECT_NE(ready->find("bridge.yaml:" + next_line(config.yaml()) + ":1: unknown key 'modbus_typo'"), std::string::npos)
      << *ready;
}

TEST_F(UnderSystemd, SigtermSendsStopping) {
  start_with({notify.environment()});
  ASSERT_TRUE(notify.wait_for("READY=1")) << daemon->log();
  daemon->signal(SIGTERM);
  EXPECT_TRUE(notify.wait_for("STOPPING=1")) << daemon->log();
  EXPECT_TRUE(eventually([&] { return !daemon->running(); }));
  EXPECT_EQ(daemon->exit_code(), 0);
}

TEST_F(UnderSystemd, WatchdogKeepAlivesKeepComing) {
  // WatchdogSec=200ms: keep-alives every 100 ms from the event loop.
  start_with({notify.environment(), "WATCHDOG_USEC=200000"});
  ASSERT_TRUE(notify.wait_for("READY=1")) << daemon->log();
  for (int i = 0; i < 3; ++i) ASSERT_TRUE(notify.wait_for("WATCHDOG=1")) << "keep-alive " << i << "\n" << daemon->log();
  EXPECT_TRUE(daemon->wait_for_log("watchdog: keep-alive every 100 ms")) << daemon->log();
}

TEST_F(UnderSystemd, AWatchdogMeantForAnotherProcessIsLeftAlone) {
  // systemd sets WATCHDOG_PID to the main process; a child that inherits it must not answer.
  start_with({notify.environment(), "WATCHDOG_USEC=200000", "WATCHDOG_PID=1"});
  ASSERT_TRUE(notify.wait_for("READY=1")) << daemon->log();
  daemon->signal(SIGTERM);
  ASSERT_TRUE(notify.wait_for("STOPPING=1")) << daemon->log();
  for (const auto& message : notify.seen()) EXPECT_FALSE(NotifySocket::carries(message, "WATCHDOG=1")) << message;
  EXPECT_EQ(daemon->log().find("watchdog:"), std::string::npos) << daemon->log();
}

/// JOURNAL_STREAM for the file the daemon's stderr will be: what systemd sets when stderr
/// is its journal stream.
std::string journal_stream_of(const std::filesystem::path& log_file) {
  std::ofstream{log_file};  // the daemon reopens it with O_TRUNC: same inode
  struct stat st {};
  if (::stat(log_file.c_str(), &st) != 0) throw std::runtime_error("stat");
  return "JOURNAL_STREAM=" + std::to_string(st.st_dev) + ":" + std::to_string(st.st_ino);
}

TEST_F(UnderSystemd, OnTheJournalLinesCarryAPriorityPrefixAndNoTime) {
  start_with({journal_stream_of(dir.path() / "daemon.log")});
  ASSERT_TRUE(daemon->wait_for_log("<6>unima-bridged ")) << daemon->log();
  daemon->rewrite_config(config.yaml() + "modbus_typo: 1\n");
  daemon->signal(SIGHUP);
  ASSERT_TRUE(daemon->wait_for_log("<3>reload failed, the running config stays: ")) << daemon->log();
  std::istringstream lines(daemon->log());
  for (std::string line; std::getline(lines, line);) {
    ASSERT_GE(line.size(), 3u);
    EXPECT_TRUE(line[0] == '<' && line[1] >= '0' && line[1] <= '7' && line[2] == '>') << line;
    EXPECT_EQ(line.find("info"), std::string::npos) << line;  // the level word is the prefix's job
  }
}

TEST_F(UnderSystemd, AnInheritedJournalStreamThatIsNotStderrIsIgnored) {
  // A program started from a service's shell inherits JOURNAL_STREAM with another stderr.
  start_with({"JOURNAL_STREAM=1:1"});
  ASSERT_TRUE(daemon->wait_for_log(" running")) << daemon->log();
  EXPECT_EQ(daemon->log().find("<6>"), std::string::npos) << daemon->log();
  EXPECT_NE(daemon->log().find(" info unima-bridged "), std::string::npos) << daemon->log();
}

}  // namespace
}  // namespace unima::test
