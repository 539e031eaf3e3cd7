// The services of the bridge (io/service.hpp), each on its own in this process over a
// real io_context and loopback sockets: what a reload's stage keeps, what its commit
// switches, and what abandon gives back when a reload is refused.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <memory>
#include <string>

#include "config/config.hpp"
#include "io/master/master_service.hpp"
#include "io/modbus/tcp_slave_service.hpp"
#include "io/monitor_service.hpp"
#include "io/http/http_service.hpp"
#include "io/mqtt/mqtt_service.hpp"
#include "io/state_service.hpp"
#include "io/status_socket_service.hpp"
#include "io/unimabus/unimabus_service.hpp"
#include "tests/support/temp_files.hpp"

namespace unima::io {
namespace {

using test_support::TempDir;

struct Services : ::testing::Test {
  TempDir dir;
  asio::io_context io;

  std::string path(const std::string& name) const { return (dir.path() / name).string(); }

  // A config of this test's directory; `more` adds top-level sections.
  config::Config load(const std::string& more, const std::string& state = "none") const {
    const auto yaml = "unimabus: { transport: sim }\n"
                      "devices: { D1: { type: unigen-chp, address: 5 } }\n"
                      "status: { socket: " + path("control.sock") + " }\n"
                      "state: { file: " + state + " }\n" + more;
    return config::load_text(yaml, path("bridge.yaml"));
  }
  std::unique_ptr<Runtime> runtime(const config::Config& config) {
    return std::make_unique<Runtime>(io, build_banks(config, nullptr));
  }
  // The next config's banks, as Bridge::reload builds them.
  std::unique_ptr<Banks> next(Runtime& runtime, const config::Config& config) {
    return build_banks(config, runtime.state.get());
  }
  // The swap of Bridge::reload, then the service's commit.
  void commit(Runtime& runtime, Service& service, std::unique_ptr<Banks> next) {
    next->store->take_state_from(*runtime.banks->store);
    const auto previous = std::exchange(runtime.banks, std::move(next));
    service.commit(*previous);
  }
  static nlohmann::json described(const Service& service) {
    status::Document status;
    service.describe(status);
    return status;
  }
  // Whether something accepts connections on 127.0.0.1:port.
  bool listening(std::uint16_t port) {
    asio::ip::tcp::socket socket(io);
    boost::system::error_code ec;
    socket.connect({asio::ip::make_address("127.0.0.1"), port}, ec);
    return !ec;
  }
  static std::uint16_t port_of(const nlohmann::json& status) {
    const std::string listen = status["ports"][0]["listen"];
    return static_cast<std::uint16_t>(std::stoi(listen.substr(listen.rfind(':') + 1)));
  }
};

TEST_F(Services, ATcpSlaveKeepsItsListenerWhenItsEndpointStaysAndTakesTheNewSettings) {
  auto rt = runtime(load("modbus: { tcp: { listen: 127.0.0.1, port: 0 } }\n"));
  TcpSlaveService tcp(*rt, TcpSlaveService::Security::plain);
  tcp.start();
  const auto port = port_of(described(tcp));
  auto banks = next(*rt, load("modbus: { tcp: { listen: 127.0.0.1, port: 0, max_clients: 3, read_only: true } }\n"));
  tcp.stage(*banks);
  commit(*rt, tcp, std::move(banks));
  EXPECT_EQ(port_of(described(tcp)), port);
  EXPECT_TRUE(listening(port));
  tcp.stop();
}

TEST_F(Services, ATcpSlaveThatCannotBindItsNewPortGivesTheRunningOneBack) {
  auto rt = runtime(load("modbus: { tcp: { listen: 127.0.0.1, port: 0 } }\n"));
  TcpSlaveService tcp(*rt, TcpSlaveService::Security::plain);
  tcp.start();
  const auto port = port_of(described(tcp));
  asio::ip::tcp::acceptor taken(io, {asio::ip::make_address("127.0.0.1"), 0});
  const auto busy = taken.local_endpoint().port();
  const auto banks = next(*rt, load("modbus: { tcp: { listen: 127.0.0.1, port: " + std::to_string(busy) + " } }\n"));
  EXPECT_THROW(tcp.stage(*banks), std::runtime_error);
  tcp.abandon();
  EXPECT_TRUE(listening(port));
  EXPECT_EQ(port_of(described(tcp)), port);
  tcp.stop();
}

TEST_F(Services, ATcpSlaveMovesToItsNewPortAtCommit) {
  auto rt = runtime(load("modbus: { tcp: { listen: 127.0.0.1, port: 0 } }\n"));
  TcpSlaveService tcp(*rt, TcpSlaveService::Security::plain);
  tcp.start();
  asio::ip::tcp::acceptor probe(io, {asio::ip::make_address("127.0.0.1"), 0});
  const auto free_port = probe.local_endpoint().port();
  probe.close();
  auto banks = next(*rt, load("modbus: { tcp: { listen: 127.0.0.1, port: " + std::to_string(free_port) + " } }\n"));
  tcp.stage(*banks);
  commit(*rt, tcp, std::move(banks));
  EXPECT_EQ(port_of(described(tcp)), free_port);
  EXPECT_TRUE(listening(free_port));
  // And a config without modbus.tcp closes it; its counters keep it listed only after traffic.
  banks = next(*rt, load(""));
  tcp.stage(*banks);
  commit(*rt, tcp, std::move(banks));
  EXPECT_FALSE(listening(free_port));
  EXPECT_TRUE(described(tcp)["ports"].empty());
}

TEST_F(Services, TheStateComesBackIntoTheBanksAndAnotherFileWaitsForTheNextStart) {
  const auto state_file = path("bridge.state");
  {
    auto rt = runtime(load("", state_file));
    const std::array<std::uint16_t, 1> value = {321};
    const auto written = rt->banks->writes->write_registers(rt->config().bank_bases[banks::index_of(banks::BankId::W)] + 2, value, nullptr);
    ASSERT_EQ(written.status, modbus::WriteResult::Status::written);
    ASSERT_GT(written.kept_as, 0u);
  }  // the state file flushes what is pending as it closes
  auto rt = runtime(load("", state_file));
  StateService state(*rt);
  EXPECT_EQ(rt->banks->store->read(banks::BankId::W, 2), 321);
  EXPECT_EQ(described(state)["state"]["file"], state_file);
  auto banks = next(*rt, load("", path("other.state")));
  state.stage(*banks);
  commit(*rt, state, std::move(banks));
  EXPECT_EQ(described(state)["state"]["file"], state_file);
}

TEST_F(Services, TheMonitorTakesItsNewFilterAtCommitAndKeepsItsLogWhenTheFileStays) {
  auto rt = runtime(load("monitor: { file: " + path("monitor.log") + " }\n"));
  MonitorService monitor(*rt);
  auto banks = next(*rt, load("monitor: { file: " + path("monitor.log") + ", filter: { address: 3 } }\n"));
  monitor.stage(*banks);
  commit(*rt, monitor, std::move(banks));
  const auto status = described(monitor);
  EXPECT_EQ(status["monitor"]["file"], path("monitor.log"));
  EXPECT_NE(status["monitor"]["filter"].get<std::string>().find("ad=3"), std::string::npos) << status["monitor"];
  EXPECT_EQ(status["indicators"].size(), rt->monitor->indicators().size());
}

TEST_F(Services, AStatusSocketThatCannotListenAtItsNewPathLeavesTheRunningOneAnswering) {
  auto rt = runtime(load(""));
  rt->status = [] { return status::Document{}; };
  StatusSocketService socket(*rt);
  socket.start();
  std::ofstream(path("file")) << "not a directory";
  auto config = load("");
  config.status.socket = path("file") + "/control.sock";  // its directory cannot be made
  auto banks = next(*rt, config);
  socket.stage(*banks);  // warned about, not refused: the socket is the operator's window
  commit(*rt, socket, std::move(banks));
  asio::local::stream_protocol::socket client(io);
  boost::system::error_code ec;
  client.connect(asio::local::stream_protocol::endpoint(path("control.sock")), ec);
  EXPECT_FALSE(ec) << ec.message();
  socket.stop();
}

TEST_F(Services, TheUnimabusSideKeepsAFeedWhoseSettingsStayAndTakesTheNewDevices) {
  const auto feed = "unix:" + path("feed.sock");
  const auto transport = "unimabus: { transport: feed, listen: " + feed + " }\n";
  auto yaml = [&](const std::string& devices) {
    return transport + "devices: " + devices + "\nstatus: { socket: " + path("control.sock") + " }\nstate: { file: none }\n";
  };
  auto rt = runtime(config::load_text(yaml("{ D1: { type: unigen-chp, address: 5 } }"), path("bridge.yaml")));
  UnimabusService unimabus(*rt);
  unimabus.start();
  asio::local::stream_protocol::socket client(io);
  client.connect(asio::local::stream_protocol::endpoint(path("feed.sock")));
  io.run_for(std::chrono::milliseconds(50));  // the feed accepts
  EXPECT_EQ(described(unimabus)["unimabus"]["clients"], 1);
  auto banks = next(*rt, config::load_text(yaml("{ D1: { type: unigen-chp, address: 5 }, D2: { type: usc, address: 6 } }"),
                                           path("bridge.yaml")));
  unimabus.stage(*banks);
  commit(*rt, unimabus, std::move(banks));
  const auto status = described(unimabus);
  EXPECT_EQ(status["unimabus"]["clients"], 1);  // the same feed, its client still connected
  EXPECT_EQ(status["devices"][1]["type"], "usc");
  unimabus.stop();
}

TEST_F(Services, HttpKeepsTheUsersReadBeforeWhenTheirFileCannotBeReadAgain) {
  const auto users = path("users");
  // A name and a crypt(3) SHA-512 hash, as http.users holds them (no login is tried here).
  std::ofstream(users) << "tech:$6$saltsalt$yc6V0zYBQ5aX0CKYjaAHMIoWEXpVFOk6Gqb1pxyGeVmZ0Lc0o5l9L9Ll2qQwYk4nBCmVUqdkaK01dHxUiLnO7/\n";
  const auto http = "http: { listen: 127.0.0.1, port: 0, users: " + users + " }\n";
  auto rt = runtime(load(http));
  HttpService service(*rt);
  std::filesystem::remove(users);
  auto banks = next(*rt, load(http));
  EXPECT_NO_THROW(service.stage(*banks));
  commit(*rt, service, std::move(banks));
  // A new config naming another file that cannot be read is refused.
  const auto elsewhere = next(*rt, load("http: { listen: 127.0.0.1, port: 0, users: " + path("missing") + " }\n"));
  EXPECT_ANY_THROW(service.stage(*elsewhere));
  service.abandon();
}

TEST_F(Services, AnMqttClientWhosePasswordCannotBeReadRefusesTheReloadAndTheRunningOneStays) {
  auto rt = runtime(load("mqtt: { broker: \"mqtt://127.0.0.1:1\", client_id: site-1 }\n"));
  MqttService mqtt(*rt);
  // The file is there when the config is checked (config/host_check refuses it otherwise)
  // and gone when the service stages it.
  test_support::write_file(path("missing"), "secret\n");
  const auto banks =
      next(*rt, load("mqtt: { broker: \"mqtt://127.0.0.1:1\", client_id: site-2, username: tech, password_file: " + path("missing") + " }\n"));
  std::filesystem::remove(path("missing"));
  EXPECT_THROW(mqtt.stage(*banks), std::runtime_error);
  mqtt.abandon();
  EXPECT_EQ(described(mqtt)["mqtt"]["client_id"], "site-1");
}

TEST_F(Services, AMasterWhoseTcpTargetIsGoneIsStagedAndSwappedAtCommit) {
  auto rt = runtime(load(""));
  MasterService master(*rt);
  EXPECT_EQ(master.master(), nullptr);  // slave mode: no master
  auto banks = next(*rt, load("modbus: { mode: master, master: { tcp: \"127.0.0.1:1\" } }\n"));
  master.stage(*banks);
  EXPECT_EQ(master.master(), nullptr);  // nothing switched before the commit
  commit(*rt, master, std::move(banks));
  EXPECT_NE(master.master(), nullptr);
}

}  // namespace
}  // namespace unima::io
