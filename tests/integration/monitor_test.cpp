// The monitor of the real daemon (SPEC §5, seed 004 §8): lines in the log for the seed's
// frames, the config's command filter, `unima-bridge monitor --follow` across the
// daemon's rotations, and `unima-bridge status` after a fault and 2 s later.

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <regex>
#include <sstream>

#include <nlohmann/json.hpp>

#include "tests/integration/bridge_fixture.hpp"
#include "tests/support/peers/cli_process.hpp"

namespace unima::test {
namespace {

using test_support::CliProcess;
using test_support::write_file;

Bytes read_query(std::uint16_t transaction, std::uint8_t unit, std::uint16_t first, std::uint16_t count) {
  return {static_cast<std::uint8_t>(transaction >> 8), static_cast<std::uint8_t>(transaction), 0x00, 0x00, 0x00, 0x06,
          unit, 0x04, static_cast<std::uint8_t>(first >> 8), static_cast<std::uint8_t>(first),
          static_cast<std::uint8_t>(count >> 8), static_cast<std::uint8_t>(count)};
}

std::string hex4(unsigned value) {
  char s[8];
  std::snprintf(s, sizeof s, "%04X", value);
  return s;
}

class Monitor : public BridgeTest {
 protected:
  void SetUp() override {
    BridgeTest::SetUp();
    log = dir.path() / "log" / "monitor.log";
  }
  void start_with(const std::string& monitor_keys) {
    config.monitor_section = "monitor:\n  file: " + log.string() + "\n" + monitor_keys;
    start();
  }
  bool log_has(const std::string& text, std::chrono::milliseconds timeout = 5000ms) const {
    return eventually([&] { return read_file(log).find(text) != std::string::npos; }, timeout);
  }
  nlohmann::json status() const {
    const auto r = run(std::string(UNIMA_BRIDGE_CLI) + " status --json --socket " + config.status_socket);
    EXPECT_EQ(r.status, 0) << r.output;
    return nlohmann::json::parse(r.output, nullptr, false);
  }
  std::filesystem::path log;
};

// The seed's example (seed 004 §5.1) with D1 offset 0 fed 0x0050, as in the TCP slave tests.
TEST_F(Monitor, EveryStateOfTheTcpSlaveGivesItsLine) {
  start_with("");
  auto feed = feed_client();
  feed_and_wait(feed, R"({"addr":5,"slot":0,"offset":0,"values":[80]})", 0x0011, 0x0050);

  ASSERT_EQ(round_trip(config.modbus_port, read_query(0x1234, 1, 0x0011, 2)).size(), 13u);
  ASSERT_EQ(round_trip(config.modbus_port, read_query(0x0002, 7, 0x0011, 1)).size(), 9u);  // Not4Me
  ASSERT_EQ(round_trip(config.modbus_port, read_query(0x0003, 1, 0x0011, 0)).size(), 9u);  // Err02
  ASSERT_EQ(round_trip(config.modbus_port, {0x00, 0x04, 0x00, 0x00, 0x00, 0x06, 0x01, 0x01, 0x00, 0x00, 0x00, 0x01})
                .size(),
            9u);  // Err01
  {
    auto socket = Socket::tcp(config.modbus_port);  // a length of 1: Err03, and the connection goes
    socket.send(Bytes{0x00, 0x05, 0x00, 0x00, 0x00, 0x01, 0x01});
    EXPECT_TRUE(socket.closed_by_peer());
  }
  ASSERT_TRUE(log_has("TrID=0005")) << read_file(log) << daemon->log();

  const std::string time = R"(\d{4}-\d\d-\d\dT\d\d:\d\d:\d\d\.\d{6}Z)";
  const std::string port = R"(tcp:127\.0\.0\.1:\d+)";
  const auto text = read_file(log);
  const std::vector<std::string> expected = {
      "Rc=12 State=Done TrID=1234 PtID=0000 Len=0006 Ad=1 PDU=04 00 11 00 02 Response=12 34 00 00 00 07 01 04 04 00 50 "
      "7F FF",
      "Rc=12 State=Not4Me TrID=0002 PtID=0000 Len=0006 Ad=7 PDU=04 00 11 00 01 Response=00 02 00 00 00 03 07 84 0B",
      "Rc=12 State=Err02 TrID=0003 PtID=0000 Len=0006 Ad=1 PDU=04 00 11 00 00 Response=00 03 00 00 00 03 01 84 02",
      "Rc=12 State=Err01 TrID=0004 PtID=0000 Len=0006 Ad=1 PDU=01 00 00 00 01 Response=00 04 00 00 00 03 01 81 01",
      "Rc=7 State=Err03 TrID=0005 PtID=0000 Len=0001 Ad=1 PDU=- Response=-",
  };
  for (const auto& rest : expected) {
    std::string pattern = rest;
    for (const char special : {'.', '-'}) {
      std::string escaped;
      for (char c : pattern) escaped += c == special ? std::string("\\") + c : std::string(1, c);
      pattern = escaped;
    }
    EXPECT_TRUE(std::regex_search(text, std::regex("(^|\n)" + time + " " + port + R"( Ix=\d+ )" + pattern + "\n")))
        << rest << "\n" << text;
  }
}

TEST_F(Monitor, TheConfigFilterKeepsOnlyMatchingQueries) {
  start_with("  filter: { address: xx, function: 6, from: 0x0100, to: 0x0101 }\n");
  ModbusClient client(config.modbus_port);
  ASSERT_TRUE(client.read_input(0x0100, 2));  // function 4: hidden
  ASSERT_TRUE(client.write(0x0102, 1));       // outside the range: hidden
  ASSERT_TRUE(client.write(0x0101, 0x0929));  // shown
  ASSERT_TRUE(log_has("PDU=06 01 01 09 29")) << read_file(log);
  const auto text = read_file(log);
  EXPECT_EQ(text.find("PDU=04"), std::string::npos) << text;
  EXPECT_EQ(text.find("PDU=06 01 02"), std::string::npos) << text;
  // Ix counts the hidden ones too.
  EXPECT_NE(text.find(" Ix=2 "), std::string::npos) << text;
}

TEST_F(Monitor, TheCliFollowsTheLogAcrossTheDaemonsRotations) {
  start_with("  max_size: 4096\n  max_files: 2\n");  // about 27 lines a file
  ASSERT_TRUE(eventually([&] { return std::filesystem::exists(log); }));
  CliProcess cli(dir.path() / "follow.out", {"monitor", "--follow", log.string()});
  constexpr int bursts = 7;
  // 1.5 kB a burst: at most one rotation between two looks of the CLI; and no more than the
  // 10 lines the CLI shows of what was there when it started.
  constexpr int per_burst = 10;
  for (int b = 0; b < bursts; ++b) {
    for (int i = 0; i < per_burst; ++i) {
      const auto transaction = static_cast<std::uint16_t>(b * per_burst + i + 1);
      ASSERT_EQ(round_trip(config.modbus_port, read_query(transaction, 1, 0x0011, 1)).size(), 11u);
    }
    const auto last = "TrID=" + hex4(static_cast<unsigned>((b + 1) * per_burst));
    ASSERT_TRUE(eventually([&] { return cli.output().find(last) != std::string::npos; }))
        << "the CLI never showed " << last << "\n" << cli.output();
  }
  EXPECT_TRUE(std::filesystem::exists(log.string() + ".1"));
  EXPECT_TRUE(std::filesystem::exists(log.string() + ".2"));
  const auto output = cli.output();
  for (int t = 1; t <= bursts * per_burst; ++t) {
    const auto tag = "TrID=" + hex4(static_cast<unsigned>(t)) + " ";
    const auto first = output.find(tag);
    EXPECT_NE(first, std::string::npos) << tag << " missing\n" << output;
    EXPECT_EQ(output.find(tag, first + 1), std::string::npos) << tag << " twice\n" << output;
  }
}

TEST_F(Monitor, TheCliReadsFiltersAndConverts) {
  start_with("  format: json\n");
  ModbusClient client(config.modbus_port);
  ASSERT_TRUE(client.read_input(0x0011, 1));
  ASSERT_TRUE(client.write(0x0100, 5));
  ASSERT_TRUE(log_has(R"("pdu":"06 01 00 00 05")")) << read_file(log);

  const std::string cli = UNIMA_BRIDGE_CLI;
  const auto all = run(cli + " monitor " + log.string());
  EXPECT_EQ(all.status, 0) << all.output;
  EXPECT_NE(all.output.find(" State=Done TrID=0001 PtID=0000 Len=0006 Ad=1 PDU=04 00 11 00 01 Response="),
            std::string::npos)
      << all.output;
  const auto writes = run(cli + " monitor --filter 'fn=6' --config " + daemon->config_path().string());
  EXPECT_EQ(writes.status, 0) << writes.output;
  EXPECT_EQ(writes.output.find("PDU=04"), std::string::npos) << writes.output;
  EXPECT_NE(writes.output.find("PDU=06 01 00 00 05"), std::string::npos) << writes.output;
  const auto json = run(cli + " monitor --json --filter 'from=0x0100 to=0x0100' " + log.string());
  EXPECT_NE(json.output.find(R"("state":"Done")"), std::string::npos) << json.output;
  EXPECT_EQ(json.output.find(R"("pdu":"04)"), std::string::npos) << json.output;

  const auto bad = run(cli + " monitor --filter 'register=5' " + log.string());
  EXPECT_EQ(bad.status, 2);
  EXPECT_NE(bad.output.find("filter: unknown key 'register' (keys: ad, fn, from, to)"), std::string::npos) << bad.output;
  const auto missing = run(cli + " monitor " + (dir.path() / "nothing.log").string());
  EXPECT_EQ(missing.status, 1);
  EXPECT_NE(missing.output.find("nothing.log: No such file or directory"), std::string::npos) << missing.output;
}

TEST_F(Monitor, StatusShowsAFaultAndTwoSecondsLaterNot) {
  start_with("  indicators: [ { address: 1, register: 0x0101 }, { address: 9, register: 0x0001 } ]\n");
  auto feed = feed_client();
  feed_and_wait(feed, R"({"addr":5,"slot":0,"offset":0,"values":[80]})", 0x0011, 0x0050);
  ModbusClient client(config.modbus_port);
  ASSERT_TRUE(client.write(0x0101, 0x0929));
  EXPECT_EQ(round_trip(config.modbus_port, read_query(0x0003, 1, 0x0011, 0)).size(), 9u);  // Err02: a fault

  const auto faulted = status();
  ASSERT_FALSE(faulted.is_discarded());
  EXPECT_TRUE(faulted["error"].get<bool>()) << faulted.dump(2);
  EXPECT_EQ(faulted["mode"], "slave");
  // The LEDs' frames: the bridge's answers (the reads of feed_and_wait, the write, the
  // Err02), the telegram received. Lit only 100 and 50 ms after each: too short to test here.
  EXPECT_GE(faulted["modbus"].value("frames", 0), 3) << faulted.dump(2);
  EXPECT_FALSE(faulted["modbus"]["last_ms_ago"].is_null());
  EXPECT_EQ(faulted["unimabus"]["frames"], 1) << faulted.dump(2);
  EXPECT_FALSE(faulted["unimabus"]["last_ms_ago"].is_null());
  EXPECT_EQ(faulted["devices"][0]["bank"], "D1");
  EXPECT_TRUE(faulted["devices"][0]["online"].get<bool>());
  EXPECT_FALSE(faulted["modules"][0]["online"].get<bool>());
  EXPECT_EQ(faulted["indicators"][0]["value"], 0x0929);
  EXPECT_EQ(faulted["indicators"][0]["access"], "write");
  EXPECT_TRUE(faulted["indicators"][1]["value"].is_null());
  const auto& tcp = faulted["ports"][0];
  EXPECT_EQ(tcp["port"], "tcp");
  EXPECT_GE(tcp["Done"].get<int>(), 2);
  EXPECT_EQ(tcp["Err02"], 1);
  // `client`; those of feed_and_wait and round_trip are gone once the daemon has seen them
  // close, which a status request may overtake.
  EXPECT_TRUE(eventually([&] { return status()["ports"][0]["clients"] == 1; })) << status().dump(2);
  EXPECT_EQ(faulted["monitor"]["dropped"], 0);

  const auto panel = run(std::string(UNIMA_BRIDGE_CLI) + " status --config " + daemon->config_path().string());
  EXPECT_EQ(panel.status, 0) << panel.output;
  EXPECT_NE(panel.output.find("Error     [*]"), std::string::npos) << panel.output;
  EXPECT_NE(panel.output.find("D1 [*] unigen-chp@5"), std::string::npos) << panel.output;
  EXPECT_NE(panel.output.find("Ad=1   Reg=0x0101  0x0929 ( 2345)  write"), std::string::npos) << panel.output;
  // On a terminal (script(1) gives it one) a lit LED is green and the Err02 counted red
  // (the Error LED's red is the unit test's: it may have gone out by now); with NO_COLOR,
  // or into a pipe as above, plain.
  const auto on_terminal = [&](const std::string& environment) {
    return run("script -qec '" + environment + std::string(UNIMA_BRIDGE_CLI) + " status --socket " + config.status_socket + "' /dev/null");
  };
  const auto coloured = on_terminal("TERM=xterm ");
  EXPECT_NE(coloured.output.find("D1 \033[32m[*]\033[0m unigen-chp@5"), std::string::npos) << coloured.output;
  EXPECT_NE(coloured.output.find("\033[1;31m      1\033[0m"), std::string::npos) << "Err02: " << coloured.output;
  const auto plain = on_terminal("TERM=xterm NO_COLOR=1 ");
  EXPECT_NE(plain.output.find("D1 [*] unigen-chp@5"), std::string::npos) << plain.output;
  EXPECT_EQ(plain.output.find("\033["), std::string::npos) << plain.output;
  EXPECT_EQ(panel.output.find('\033'), std::string::npos) << panel.output;

  // The Error LED goes out 2 s after the last fault (seed 004 §8).
  EXPECT_TRUE(eventually([&] { return status()["error"] == false; }, 6000ms));
  const auto cleared = run(std::string(UNIMA_BRIDGE_CLI) + " status --socket " + config.status_socket);
  EXPECT_NE(cleared.output.find("Error     [ ]"), std::string::npos) << cleared.output;
}

// Out of descriptors, the status socket's accept fails like the others' and waits
// before it tries again instead of spinning; once descriptors are free it answers again.
TEST_F(Monitor, OutOfDescriptorsTheStatusSocketWaitsInsteadOfSpinningAndRecovers) {
  UNIMA_SKIP_WHEN_SANITIZED();
  daemon = start_with_few_descriptors(dir, config.yaml(), config.modbus_port);
  auto clients = tcp_clients(config.modbus_port, 40);
  // The TCP slave makes room for each new client (SPEC §10); the descriptors stay used up.
  ASSERT_TRUE(daemon->wait_for_log("modbus tcp: out of file descriptors")) << daemon->log().substr(0, 2000);
  for (int i = 0; i < 3; ++i) clients.push_back(Socket::unix_socket(config.status_socket));  // the backlog takes them
  std::string report;
  EXPECT_TRUE(daemon->logs_slowly("status: accept failed", report)) << report;
  clients.clear();
  EXPECT_TRUE(eventually([&] {
    return run(std::string(UNIMA_BRIDGE_CLI) + " status --json --socket " + config.status_socket).status == 0;
  })) << daemon->log().substr(0, 2000);
}

TEST_F(Monitor, AReloadSwitchesTheLogAndTheFilterAndKeepsTheIndicators) {
  start_with("  indicators: [ { address: 1, register: 0x0100 } ]\n");
  ModbusClient client(config.modbus_port);
  ASSERT_TRUE(client.write(0x0100, 0x0101));
  ASSERT_TRUE(log_has("PDU=06 01 00 01 01")) << read_file(log);

  const auto other_log = dir.path() / "other.log";
  auto reloaded = config;
  reloaded.monitor_section = "monitor:\n  file: " + other_log.string() +
                             "\n  filter: { function: 6 }\n  indicators: [ { address: 1, register: 0x0100 } ]\n";
  daemon->rewrite_config(reloaded.yaml());
  daemon->signal(SIGHUP);
  ASSERT_TRUE(daemon->wait_for_log("bridge: reloaded")) << daemon->log();
  ASSERT_TRUE(client.read_input(0x0011, 1));  // hidden by the new filter
  ASSERT_TRUE(client.write(0x0100, 0x0202));
  ASSERT_TRUE(eventually([&] { return read_file(other_log).find("PDU=06 01 00 02 02") != std::string::npos; }))
      << read_file(other_log) << daemon->log();
  EXPECT_EQ(read_file(other_log).find("PDU=04"), std::string::npos) << read_file(other_log);
  EXPECT_EQ(read_file(log).find("PDU=06 01 00 02 02"), std::string::npos) << read_file(log);
  const auto s = status();
  EXPECT_EQ(s["indicators"][0]["value"], 0x0202);
  EXPECT_EQ(s["monitor"]["file"], other_log.string());
  EXPECT_EQ(s["monitor"]["filter"], "ad=xx fn=6 from=0x0000 to=0xFFFF");
  EXPECT_GE(s["ports"][0]["Done"].get<int>(), 3);  // counters go on across the reload
}

// The installed bridge.yaml sets no monitor.file: "No such file" alone left the operator
// guessing which path was tried and which key would give one (issue 30, point 8).
TEST(MonitorCommand, ALogThatIsNotThereSaysWhichPathWasTriedAndWhichKeyToSet) {
  const std::filesystem::path default_log = "/var/log/unima-bridge/monitor.log";
  if (std::filesystem::exists(default_log)) GTEST_SKIP() << default_log << " exists on this machine";
  TempDir dir;
  const auto config = dir.path() / "bridge.yaml";
  write_file(config, "log: { level: info }\nstate: { file: none }\n");
  const std::string cli = UNIMA_BRIDGE_CLI;

  const auto without_file = run(cli + " monitor --config " + config.string());
  EXPECT_EQ(without_file.status, 1);
  EXPECT_NE(without_file.output.find("cannot open /var/log/unima-bridge/monitor.log: No such file or directory"),
            std::string::npos)
      << without_file.output;
  EXPECT_NE(without_file.output.find(config.string() + " sets no monitor.file; set monitor.file there"),
            std::string::npos)
      << without_file.output;

  const auto without_config = run(cli + " monitor");
  EXPECT_EQ(without_config.status, 1);
  EXPECT_NE(without_config.output.find("no --config was given; give --config FILE"), std::string::npos)
      << without_config.output;

  write_file(config, "monitor: { file: " + (dir.path() / "monitor.log").string() + " }\nstate: { file: none }\n");
  const auto not_yet_written = run(cli + " monitor --config " + config.string());
  EXPECT_EQ(not_yet_written.status, 1);
  EXPECT_NE(not_yet_written.output.find("it is monitor.file of " + config.string()), std::string::npos)
      << not_yet_written.output;
}

TEST(StatusCommand, ADaemonThatDoesNotAnswerIsAnErrorNamingTheSocket) {
  const auto r = run(std::string(UNIMA_BRIDGE_CLI) + " status --socket /nonexistent/control.sock");
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.output.find("cannot reach the daemon on /nonexistent/control.sock"), std::string::npos) << r.output;
  EXPECT_EQ(run(std::string(UNIMA_BRIDGE_CLI) + " status --frobnicate").status, 2);
}

}  // namespace
}  // namespace unima::test
