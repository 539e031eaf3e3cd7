// Paths and addresses are not trusted (SPEC §10, issue 17 item 5): a socket path that names
// anything but a socket is refused and never removed; the monitor and record files refuse
// a symbolic link; and `unima-bridge check` refuses exactly the addresses the daemon
// cannot use, with file:line:column — at start-up (exit 1) and on reload (the running
// config stays).

#include <signal.h>
#include <sys/stat.h>

#include <filesystem>

#include "config/config.hpp"
#include "config/socket_path.hpp"
#include "io/control_socket.hpp"
#include "io/unimabus/feed_transport.hpp"
#include "tests/integration/bridge_fixture.hpp"

namespace unima::test {
namespace {

namespace fs = std::filesystem;

constexpr const char* precious = "precious, not the daemon's\n";

class Paths : public BridgeTest {
 protected:
  /// Starts the daemon on `config` and waits for it to exit, as it must.
  void expect_refused_start(const std::string& must_log) {
    daemon = std::make_unique<Daemon>(dir, config.yaml());
    ASSERT_TRUE(eventually([&] { return !daemon->running(); })) << daemon->log();
    EXPECT_EQ(daemon->exit_code(), 1) << daemon->log();
    EXPECT_NE(daemon->log().find(must_log), std::string::npos) << daemon->log();
  }
  /// A file that is not the daemon's, with content it must never lose.
  fs::path precious_file(const std::string& name) const {
    const auto path = dir.path() / name;
    test_support::write_file(path, precious);
    return path;
  }
  void expect_untouched(const fs::path& path) const { EXPECT_EQ(read_file(path), precious) << path; }
  /// `unima-bridge check` on `yaml`: its exit status and output.
  CommandResult check(const std::string& yaml) const {
    const auto file = dir.path() / "checked.yaml";
    test_support::write_file(file, yaml);
    return run(std::string(UNIMA_BRIDGE_CLI) + " check --config " + file.string());
  }
};

TEST_F(Paths, AStatusSocketPathNamingAFileIsAStartUpErrorAndTheFileStays) {
  const auto file = precious_file("control.sock");
  config.status_socket = file.string();
  expect_refused_start("status.socket: " + file.string() + " names a regular file, not a socket");
  expect_untouched(file);
}

TEST_F(Paths, AStatusSocketPathNamingASymbolicLinkOrADirectoryIsRefusedToo) {
  const auto target = precious_file("target");
  const auto link = dir.path() / "link.sock";
  fs::create_symlink(target, link);
  config.status_socket = link.string();
  expect_refused_start("status.socket: " + link.string() + " names a symbolic link, not a socket");
  EXPECT_TRUE(fs::is_symlink(link));
  expect_untouched(target);

  const auto directory = dir.path() / "run";
  fs::create_directory(directory);
  config.status_socket = directory.string();
  expect_refused_start("status.socket: " + directory.string() + " names a directory, not a socket");
  EXPECT_TRUE(fs::is_directory(directory));
}

// A stale socket is still replaced; and what took a socket's place while the daemon ran is
// not removed when it stops.
TEST_F(Paths, AStaleStatusSocketIsReplacedAndAtStopOnlyASocketIsRemoved) {
  start();
  // The status socket is bound after the Modbus port start() waits for.
  ASSERT_TRUE(eventually([&] { return Socket::unix_socket(config.status_socket).valid(); })) << daemon->log();
  daemon->signal(SIGKILL);  // leaves its socket file behind
  ASSERT_TRUE(eventually([&] { return !daemon->running(); }));
  ASSERT_TRUE(fs::is_socket(config.status_socket));
  start();
  EXPECT_TRUE(eventually([&] { return Socket::unix_socket(config.status_socket).valid(); })) << daemon->log();
  // Group members ask it (0660), whatever the umask; the mode is set on the socket itself.
  struct stat st{};
  ASSERT_EQ(::lstat(config.status_socket.c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 0777, 0660u);
  daemon->terminate();
  EXPECT_FALSE(fs::exists(fs::symlink_status(config.status_socket)));  // its own socket goes with it

  config.feed_listen = "unix:" + (dir.path() / "feed.sock").string();
  start();
  ASSERT_TRUE(eventually([&] { return Socket::unix_socket(config.status_socket).valid(); })) << daemon->log();
  ASSERT_TRUE(eventually([&] { return fs::is_socket(config.feed_listen.substr(5)); })) << daemon->log();
  for (const auto& socket : {config.status_socket, config.feed_listen.substr(5)})
    fs::rename(precious_file("replacement"), socket);  // someone's file where the socket was
  daemon->terminate();
  expect_untouched(config.status_socket);
  expect_untouched(config.feed_listen.substr(5));
}

TEST_F(Paths, AFeedSocketPathNamingAFileIsAStartUpErrorAndTheFileStays) {
  const auto file = precious_file("feed.sock");
  config.feed_listen = "unix:" + file.string();
  expect_refused_start("unimabus.listen: " + file.string() + " names a regular file, not a socket");
  expect_untouched(file);
}

TEST_F(Paths, AMonitorFileThatIsASymbolicLinkIsAStartUpErrorAndItsTargetStays) {
  const auto target = precious_file("target");
  const auto link = dir.path() / "monitor.log";
  fs::create_symlink(target, link);
  config.monitor_section = "monitor:\n  file: " + link.string() + "\n";
  expect_refused_start("monitor.file: " + link.string() + " is a symbolic link");
  expect_untouched(target);
}

TEST_F(Paths, ARecordFileThatIsASymbolicLinkIsAStartUpErrorAndItsTargetStays) {
  const auto target = precious_file("target");
  const auto link = dir.path() / "unimabus.jsonl";
  fs::create_symlink(target, link);
  config.unimabus_extra = "  record: { file: " + link.string() + " }\n";
  expect_refused_start("unimabus.record.file: " + link.string() + " is a symbolic link");
  expect_untouched(target);
}

TEST_F(Paths, AReloadToASymbolicLinkOrAFileKeepsTheRunningConfig) {
  const auto log = dir.path() / "monitor.log";
  config.monitor_section = "monitor:\n  file: " + log.string() + "\n";
  start();
  ModbusClient client(config.modbus_port);
  ASSERT_TRUE(client.write(0x0100, 7));

  const auto target = precious_file("target");
  const auto link = dir.path() / "other.log";
  fs::create_symlink(target, link);
  auto reloaded = config;
  reloaded.monitor_section = "monitor:\n  file: " + link.string() + "\n";
  daemon->rewrite_config(reloaded.yaml());
  daemon->signal(SIGHUP);
  ASSERT_TRUE(daemon->wait_for_log("reload failed, the running config stays")) << daemon->log();
  EXPECT_NE(daemon->log().find("monitor.file: " + link.string() + " is a symbolic link"), std::string::npos)
      << daemon->log();

  const auto file = precious_file("control.sock.new");
  reloaded = config;
  reloaded.status_socket = file.string();
  daemon->rewrite_config(reloaded.yaml());
  daemon->signal(SIGHUP);
  ASSERT_TRUE(eventually([&] { return daemon->log_count("reload failed, the running config stays") == 2; }))
      << daemon->log();
  EXPECT_NE(daemon->log().find("status.socket: " + file.string() + " names a regular file"), std::string::npos)
      << daemon->log();

  // The old log, the old status socket and the values stay; nothing was written elsewhere.
  ASSERT_TRUE(client.write(0x0100, 8));
  EXPECT_TRUE(eventually([&] { return read_file(log).find("PDU=06 01 00 00 08") != std::string::npos; }))
      << read_file(log);
  EXPECT_TRUE(Socket::unix_socket(config.status_socket).valid());
  expect_untouched(target);
  expect_untouched(file);
  EXPECT_TRUE(daemon->running());
}

// The daemon checks again where it removes a socket file, whatever the loader saw: the
// file system may have changed since.
TEST(PathsInProcess, TheListenersThemselvesNeverRemoveAnythingButASocket) {
  TempDir dir;
  const auto file = dir.path() / "taken";
  test_support::write_file(file, precious);
  asio::io_context io;
  EXPECT_THROW(io::ControlSocket(io, file.string(), [] { return std::string(); }), config::PathRefused);
  config::ListenEndpoint endpoint;
  endpoint.text = "unix:" + file.string();
  endpoint.unix_path = file.string();
  try {
    io::FeedTransport feed(io, endpoint, 1, [](const unimabus::Telegram&) { return std::string(); },
                           [] { return std::string(); });
    ADD_FAILURE() << "listened";
  } catch (const config::PathRefused& e) {
    EXPECT_EQ(std::string(e.what()),
              "unimabus.listen: " + file.string() + " names a regular file, not a socket; the daemon never removes it "
              "to listen there");
  }
  EXPECT_EQ(read_file(file), precious);
}

// The two configs `check` passed while the daemon stopped with a bare "Invalid argument".
TEST_F(Paths, CheckAndTheDaemonRefuseTheSameAddressesNamingThePosition) {
  config.feed_listen = "localhost:5000";
  const std::string feed_error =
      ":4:11: 'localhost:5000': 'localhost' is a name; the daemon listens on an IP address of this machine";
  auto checked = check(config.yaml());
  EXPECT_EQ(checked.status, 1) << checked.output;
  EXPECT_NE(checked.output.find("checked.yaml" + feed_error), std::string::npos) << checked.output;
  expect_refused_start("bridge.yaml" + feed_error);

  config.feed_listen.clear();
  auto yaml = config.yaml();
  const auto at = yaml.find("listen: 127.0.0.1, port");
  ASSERT_NE(at, std::string::npos) << yaml;
  yaml.replace(at, 17, "listen: 999.1.1.1");
  checked = check(yaml);
  EXPECT_EQ(checked.status, 1) << checked.output;
  EXPECT_NE(checked.output.find("checked.yaml:7:18: '999.1.1.1' is not an IP address"), std::string::npos)
      << checked.output;
  daemon = std::make_unique<Daemon>(dir, yaml);
  ASSERT_TRUE(eventually([&] { return !daemon->running(); }));
  EXPECT_EQ(daemon->exit_code(), 1);
  EXPECT_NE(daemon->log().find("bridge.yaml:7:18: '999.1.1.1' is not an IP address"), std::string::npos)
      << daemon->log();
  EXPECT_EQ(daemon->log().find("Invalid argument"), std::string::npos) << daemon->log();
}

TEST_F(Paths, CheckRefusesASocketPathNamingAFileAsTheDaemonDoes) {
  const auto file = precious_file("control.sock");
  config.status_socket = file.string();
  const auto checked = check(config.yaml());
  EXPECT_EQ(checked.status, 1) << checked.output;
  EXPECT_NE(checked.output.find("status.socket: " + file.string() + " names a regular file, not a socket"),
            std::string::npos)
      << checked.output;
  expect_untouched(file);
}

// SPEC §10: the state is read at start and rewritten beside itself. A FIFO there used to
// hang the start with no port and no log line; a FIFO, a directory or a device is refused
// at once, by `check` as by the daemon, naming the key and its position.
TEST_F(Paths, AStateFilePathThatIsNotARegularFileIsRefusedAtStartNamingTheKey) {
  const auto fifo = dir.path() / "bridge.state";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  config.extra = "state: { file: " + fifo.string() + " }\n";
  const auto checked = check(config.yaml());
  EXPECT_EQ(checked.status, 1) << checked.output;
  EXPECT_NE(checked.output.find("state.file: " + fifo.string() + " is a FIFO, not a regular file"), std::string::npos)
      << checked.output;
  expect_refused_start("state.file: " + fifo.string() + " is a FIFO, not a regular file");

  const auto directory = dir.path() / "state-dir";
  fs::create_directory(directory);
  config.extra = "state: { file: " + directory.string() + " }\n";
  expect_refused_start("state.file: " + directory.string() + " is a directory, not a regular file");
}

// A feed port another program holds: the error names the key, not a bare "bind: ...".
TEST_F(Paths, AFeedPortThatIsTakenIsAnErrorNamingTheKey) {
  asio::io_context io;
  asio::ip::tcp::acceptor holder(io, asio::ip::tcp::endpoint(asio::ip::make_address("127.0.0.1"), config.feed_port));
  const auto address = "127.0.0.1:" + std::to_string(config.feed_port);
  expect_refused_start(":4:11: unimabus.listen " + address + ": address " + address + " is in use by another program");
}

}  // namespace
}  // namespace unima::test
