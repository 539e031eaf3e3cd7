// Master mode end to end (issue #6, seed 004 §7.2, SPEC §4): the daemon drives simulated
// foreign slaves (tests/sim) over a pseudo-terminal or TCP. The bytes are checked where a
// slave would see them: the simulator's frame log.

#include <signal.h>
#include <sys/wait.h>

#include <cstdio>
#include <fstream>
#include <set>

#include <nlohmann/json.hpp>

#include "tests/integration/master_fixture.hpp"

namespace unima::test {
namespace {

std::size_t count_frames(const std::vector<SimFrame>& frames, const std::string& hex, bool rx = true) {
  std::size_t n = 0;
  for (const auto& f : frames) n += f.rx == rx && f.hex == hex;
  return n;
}

bool log_has(const Daemon& daemon, const std::string& text) { return daemon.log().find(text) != std::string::npos; }

// SPEC §8: in master mode the Modbus LED shows each query the bridge sends, answered or
// not — lit when it goes on the line, not when its answer or time-out comes.
TEST_F(MasterTest, TheModbusLedShowsEveryQuerySentAnsweredOrNot) {
  simulate({"1=sic184-v3,dead"});
  config.master = "retries: 0, degrade_after: 100, response_timeout: 300ms";
  config.blocks = "  - { type: poll, device: 1, profile: sic184-v3, point: STATUS, period: 100ms, output: 1 }\n";
  start();
  const auto status = [&] {
    const auto r = run(std::string(UNIMA_BRIDGE_CLI) + " status --json --socket " + config.status_socket);
    return nlohmann::json::parse(r.output, nullptr, false);
  };
  const auto queries = [&] {
    std::size_t n = 0;
    for (const auto& f : sim->frames()) n += f.rx;
    return n;
  };
  ASSERT_TRUE(eventually([&] { return queries() >= 3; })) << diagnostics();
  // Every query counts, none was answered; a status within 100 ms of one sees it lit.
  EXPECT_GE(status()["modbus"].value("frames", std::size_t{0}), 3u) << status().dump();
  EXPECT_TRUE(eventually([&] { return status()["modbus"]["active"] == true; })) << status().dump();
}

TEST_F(MasterTest, Sic184V3SeedFramesOnTheWire) {
  simulate({"1=sic184-v3"});
  config.blocks =
      "  - { type: poll, device: 1, profile: sic184-v3, point: IN, period: 200ms, output: 1 }\n"
      "  - { type: send, device: 1, point: OUT2, period: 200ms, source: X.0 }\n"
      "  - { type: poll, device: 1, point: POS_ACT_REAL, period: 200ms, output: 2 }\n";
  start();
  // Seed 000 §3.1: reading IN1 (eight inputs from 5000) and setting OUT2 (6001) off;
  // §3.2: reading POS_ACT_REAL (1060).
  EXPECT_TRUE(sim->wait_for_frame("01 02 13 88 00 08 FD 62")) << diagnostics();
  EXPECT_TRUE(sim->wait_for_frame("01 05 17 71 00 00 98 65")) << diagnostics();
  EXPECT_TRUE(sim->wait_for_frame("01 03 04 24 00 02 85 30")) << diagnostics();
  // The values, into user analog outputs 1 and 2: inputs IN1 and IN3 on; 4.5 in 0.1 units.
  EXPECT_TRUE(output_becomes(1, 0x05)) << diagnostics();
  EXPECT_TRUE(output_becomes(2, 45)) << diagnostics();
  EXPECT_EQ(sim->control("coil 1 6001"), "coil 0");
  // X.0 on: the next send sets OUT2.
  ModbusClient client(config.modbus_port);
  ASSERT_TRUE(client.write(x_bank, 1));
  EXPECT_TRUE(sim->wait_for_frame("01 05 17 71 FF 00 D9 95")) << diagnostics();
  EXPECT_TRUE(eventually([&] { return sim->control("coil 1 6001") == "coil 1"; })) << diagnostics();
}

// 14400 baud has no termios constant: the master opens its line the way the slave port does
// (io/modbus/serial_line), through termios2, instead of failing to start.
TEST_F(MasterTest, AMasterLineAt14400BaudOpensAndPolls) {
  simulate({"1=sic184-v3"});
  config.line = "rtu: { device: " + sim->pty() + ", baud: 14400 }";
  config.blocks = "  - { type: poll, device: 1, profile: sic184-v3, point: IN, period: 200ms, output: 1 }\n";
  start();
  EXPECT_TRUE(sim->wait_for_frame("01 02 13 88 00 08 FD 62")) << diagnostics();
  EXPECT_TRUE(output_becomes(1, 0x05)) << diagnostics();
  EXPECT_TRUE(log_has(*daemon, "modbus master: rtu " + sim->pty() + " 14400 8N1")) << diagnostics();
}

// Seed 003: the WECON LX5V named by its own operands — D200, the input X17 (octal: the
// 16th input), a 32-bit D210/D211 pair low word first, and the output Y10 (the 9th).
TEST_F(MasterTest, AWeconPlcIsPolledAndWrittenByItsOperands) {
  simulate({"3=wecon-lx5v"});
  config.blocks =
      "  - { type: poll, device: 3, profile: wecon-lx5v, operand: D200, period: 200ms, output: 1 }\n"
      "  - { type: poll, device: 3, operand: X17, period: 200ms, output: 2 }\n"
      "  - { type: poll, device: 3, operand: D210, data_type: dint, period: 200ms, output: 3 }\n"
      "  - { type: send, device: 3, operand: Y10, period: 200ms, source: X.0 }\n";
  ASSERT_EQ(sim->control("set 3 200 1234"), "ok");
  ASSERT_EQ(sim->control("input 3 63503 1"), "ok");  // 0xF800 + 15
  ASSERT_EQ(sim->control("set 3 210 16"), "ok");     // low word
  ASSERT_EQ(sim->control("set 3 211 0"), "ok");      // high word
  start();
  EXPECT_TRUE(sim->wait_for_frame("03 03 00 C8 00 01 04 16")) << diagnostics();  // D200: function 3, address 200
  EXPECT_TRUE(sim->wait_for_frame("03 02 F8 0F 00 01 B9 4B")) << diagnostics();  // X17: function 2, 0xF80F
  EXPECT_TRUE(output_becomes(1, 1234)) << diagnostics();
  EXPECT_TRUE(output_becomes(2, 1)) << diagnostics();
  EXPECT_TRUE(output_becomes(3, 16)) << diagnostics();  // high word first would read 0x00100000: out of range
  EXPECT_EQ(sim->control("coil 3 64520"), "coil 0");   // Y10 = 0xFC00 + 8
  ModbusClient client(config.modbus_port);
  ASSERT_TRUE(client.write(x_bank, 1));
  EXPECT_TRUE(eventually([&] { return sim->control("coil 3 64520") == "coil 1"; })) << diagnostics();
}

TEST_F(MasterTest, TheMonitorLogsEveryMasterTransaction) {
  simulate({"1=sic184-v3"});
  const auto log = dir.path() / "monitor.log";
  config.extra = "monitor: { file: " + log.string() + " }\n";
  config.blocks = "  - { type: poll, device: 1, profile: sic184-v3, point: IN1, period: 200ms, output: 1 }\n";
  start();
  ASSERT_TRUE(sim->wait_for_frame("01 02 13 88 00 01 3D 64")) << diagnostics();
  std::string text;
  ASSERT_TRUE(eventually([&] {
    std::ifstream in(log);
    text.assign(std::istreambuf_iterator<char>(in), {});
    return text.find(" master Ix=") != std::string::npos;
  })) << diagnostics();
  EXPECT_NE(text.find(" Rc=8 State=Done Ad=1 PDU=02 13 88 00 01 CRC=3D64 Response=01 02 01 01 60 48\n"), std::string::npos)
      << text;
}

TEST_F(MasterTest, StepperDriverSeedFramesOnTheWire) {
  simulate({"1=stepper-driver"});
  config.blocks =
      "  - { type: poll, device: 1, profile: stepper-driver, point: STEP_ANGLE, period: 300ms, output: 1 }\n"
      "  - { type: poll, device: 1, point: SUBDIVISION, period: 300ms, output: 2 }\n"
      "  - { type: send, device: 1, point: SINGLE_RUN, period: 300ms, source: X.0 }\n"
      "  - { type: send, device: 1, point: SUBDIVISION, period: 300ms, source: W+0x00 }\n"
      "  - { type: send, device: 1, point: TEST_DISTANCE, period: 300ms, source: W+0x01 }\n";
  start();
  // Seed 002 §6 (1): the two registers in one request, and the seed's response.
  EXPECT_TRUE(sim->wait_for_frame("01 03 00 00 00 02 C4 0B")) << diagnostics();
  EXPECT_TRUE(sim->wait_for_frame("01 03 04 00 B4 00 08 BB D3", false)) << diagnostics();
  EXPECT_TRUE(output_becomes(1, 18)) << diagnostics();  // 1.80° in 0.1°
  EXPECT_TRUE(output_becomes(2, 8)) << diagnostics();
  // W is "not measured" until written: nothing goes to registers 1 and 9 before.
  const auto before = sim->frames();
  for (const auto& f : before) EXPECT_FALSE(f.rx && (f.hex.starts_with("01 06") || f.hex.starts_with("01 10"))) << f.hex;
  ModbusClient client(config.modbus_port);
  ASSERT_TRUE(client.write(x_bank, 1));
  ASSERT_TRUE(client.write(w_bank, 4));
  ASSERT_TRUE(client.write(w_bank + 1, 200));
  // §6 (2) coil 00008 on, (3) register 40002 = 4, (4) 200 into 40010/40011, low word first.
  EXPECT_TRUE(sim->wait_for_frame("01 05 00 07 FF 00 3D FB")) << diagnostics();
  EXPECT_TRUE(sim->wait_for_frame("01 06 00 01 00 04 D9 C9")) << diagnostics();
  EXPECT_TRUE(sim->wait_for_frame("01 10 00 09 00 02 04 00 C8 00 00 B2 3B")) << diagnostics();
  EXPECT_TRUE(sim->wait_for_frame("01 10 00 09 00 02 91 CA", false)) << diagnostics();
  EXPECT_TRUE(output_becomes(2, 4)) << diagnostics();  // the poll reads back what the send wrote
  EXPECT_EQ(sim->control("get 1 9"), "value 200");
}

TEST_F(MasterTest, TheStepperDriverGetsAFrameEvery35MillisecondsAtMost) {
  simulate({"1=stepper-driver"});
  // Three requests of 20 ms: 150 frames a second asked, the driver takes 28.6.
  config.blocks =
      "  - { type: poll, device: 1, profile: stepper-driver, point: STEP_ANGLE, period: 20ms, output: 1 }\n"
      "  - { type: poll, device: 1, point: TEST_SPEED, period: 20ms, output: 2 }\n"
      "  - { type: poll, device: 1, point: POSITION, period: 20ms, output: 3 }\n";
  start();
  std::vector<std::int64_t> arrivals;
  ASSERT_TRUE(eventually([&] {
    arrivals.clear();
    for (const auto& f : sim->frames())
      if (f.rx) arrivals.push_back(f.micros);
    return arrivals.size() >= 30;
  })) << diagnostics();
  // Single gaps as seen here carry the pseudo-terminal's delivery jitter (the rule itself
  // is unit-tested): the frames on average.
  const auto average_gap = (arrivals.back() - arrivals.front()) / static_cast<std::int64_t>(arrivals.size() - 1);
  EXPECT_GE(average_gap, 34'500) << diagnostics();
  EXPECT_LE(average_gap, 45'000) << "the line idles although requests are due\n" << diagnostics();
  EXPECT_TRUE(output_becomes(1, 18) && output_becomes(2, 60) && output_becomes(3, 1234)) << diagnostics();
}

TEST_F(MasterTest, ConsecutiveBlocksShareOneRequestCountedAtTheSlave) {
  simulate({"1=sic184-v3"});
  // Eight single inputs and four single registers: two requests per period, not twelve.
  for (int n = 1; n <= 8; ++n)
    config.blocks += "  - { type: poll, device: 1, profile: sic184-v3, point: IN" + std::to_string(n) +
                     ", period: 100ms, output: " + std::to_string(n) + " }\n";
  config.blocks +=
      "  - { type: poll, device: 1, point: STATUS, period: 100ms, output: 9 }\n"
      "  - { type: poll, device: 1, point: POWER, period: 200ms, output: 10 }\n"
      "  - { type: poll, device: 1, point: POWER_RED, period: 300ms, output: 11 }\n"
      "  - { type: poll, device: 1, point: JOG_SPEED, period: 400ms, output: 12 }\n";
  start();
  ASSERT_TRUE(output_becomes(12, 10)) << diagnostics();
  ASSERT_EQ(sim->control("reset"), "ok");
  ASSERT_TRUE(eventually([&] { return sim->control("count 1") == "count 20"; })) << diagnostics();
  const auto frames = sim->frames();
  std::set<std::string> requests;
  for (const auto& f : frames)
    if (f.rx) requests.insert(f.hex);
  // The merged IN1..IN8 is exactly the seed's frame for reading IN1.
  EXPECT_EQ(requests, (std::set<std::string>{"01 02 13 88 00 08 FD 62", "01 03 03 EA 00 04 65 B9"})) << diagnostics();
  // Both go every 100 ms (the shortest period): equal counts, one frame each per period.
  const auto bits = count_frames(frames, "01 02 13 88 00 08 FD 62");
  const auto registers = count_frames(frames, "01 03 03 EA 00 04 65 B9");
  EXPECT_LE(bits > registers ? bits - registers : registers - bits, 1u);
  EXPECT_TRUE(output_becomes(1, 1) && output_becomes(2, 0) && output_becomes(3, 1)) << diagnostics();
  EXPECT_EQ(output(9), 1);   // STATUS
  EXPECT_EQ(output(10), 80);  // POWER
}

TEST_F(MasterTest, AGapMergeFallsBackToSplitRequestsAfterException02) {
  simulate({"1=sic184-v3"});
  config.master = "merge_gap: 20";
  config.blocks =
      "  - { type: poll, device: 1, profile: sic184-v3, point: STATUS, period: 200ms, output: 1 }\n"
      "  - { type: poll, device: 1, point: POS_ACT_INT, scale: 0.01, period: 200ms, output: 2 }\n";
  start();
  // 1002..1021 in one request; registers 1006..1019 do not exist on the SIC184.
  EXPECT_TRUE(sim->wait_for_frame("01 03 03 EA 00 14 64 75")) << diagnostics();
  EXPECT_TRUE(sim->wait_for_frame("01 83 02 C0 F1", false)) << diagnostics();
  EXPECT_TRUE(sim->wait_for_frame("01 03 03 EA 00 01 A5 BA")) << diagnostics();
  EXPECT_TRUE(sim->wait_for_frame("01 03 03 FC 00 02 04 7F")) << diagnostics();
  EXPECT_TRUE(output_becomes(1, 1)) << diagnostics();
  EXPECT_TRUE(output_becomes(2, 576)) << diagnostics();  // 57600 pulses x 0.01
  EXPECT_EQ(count_frames(sim->frames(), "01 03 03 EA 00 14 64 75"), 1u) << "the merge was tried again";
  EXPECT_TRUE(log_has(*daemon, "answered exception 02 to function 3 1002..1021; reading it in 2 requests")) << diagnostics();
}

struct FaultCase {
  std::string garbage;
  std::string state;
};

TEST_F(MasterTest, FaultsGoToTheMonitorHookTheErrorBitAndTheCounters) {
  simulate({"1=sic184-v3"});
  config.master = "retries: 0, degrade_after: 100";
  config.blocks = "  - { type: poll, device: 1, profile: sic184-v3, point: POS_ACT_REAL, period: 100ms, output: 1 }\n";
  start();
  ASSERT_TRUE(output_becomes(1, 45)) << diagnostics();
  ModbusClient client(config.modbus_port);
  const auto error_bit = [&] {
    const auto v = client.read_input(online_bits, 1);
    return v && ((*v)[0] & 0x8000) != 0;
  };
  EXPECT_TRUE(eventually([&] { return !error_bit(); }, 4000ms)) << "C+0x13 bit 15 set without a fault";
  const std::vector<FaultCase> cases{{"crc", "Err03"}, {"short", "Err04"}, {"function", "Err04"}, {"address", "Err04"},
                                     {"noise", "Err04"}};
  for (const auto& c : cases) {
    ASSERT_EQ(sim->control("garbage 1 " + c.garbage), "ok");
    EXPECT_TRUE(daemon->wait_for_log("modbus master: " + c.state + " rtu 01 03 04 24 00 02 85 30 -> ")) << c.garbage << "\n"
                                                                                                       << diagnostics();
    EXPECT_TRUE(eventually(error_bit)) << c.garbage;
  }
  ASSERT_EQ(sim->control("garbage 1 off"), "ok");
  ASSERT_EQ(sim->control("exception 1 4"), "ok");
  EXPECT_TRUE(daemon->wait_for_log("modbus master: Err04 rtu 01 03 04 24 00 02 85 30 -> 01 83 04 40 F3")) << diagnostics();
  ASSERT_EQ(sim->control("exception 1 off"), "ok");
  ASSERT_EQ(sim->control("dead 1 on"), "ok");
  EXPECT_TRUE(daemon->wait_for_log("modbus master: Timeout rtu 01 03 04 24 00 02 85 30 -> -")) << diagnostics();
  ASSERT_EQ(sim->control("dead 1 off"), "ok");
  // The last good value stayed through all of it (stale_after is 10 s), and the error bit
  // goes 2 s after the last fault.
  EXPECT_EQ(output(1), 45);
  EXPECT_TRUE(eventually([&] { return !error_bit(); }, 5000ms)) << diagnostics();
  const auto took = daemon->terminate();
  ASSERT_TRUE(took);
  EXPECT_TRUE(eventually([&] { return log_has(*daemon, "modbus master: device 1: "); })) << diagnostics();
  const auto log = daemon->log();
  const auto counters = log.substr(log.find("modbus master: device 1: "));
  EXPECT_NE(counters.find("time-outs"), std::string::npos);
  EXPECT_EQ(counters.find(" 0 bad frames"), std::string::npos) << counters;
  EXPECT_EQ(counters.find(" 0 exceptions"), std::string::npos) << counters;
}

TEST_F(MasterTest, ALastGoodValueStaysUntilStaleThenReads7FFF) {
  simulate({"1=sic184-v3"});
  config.master = "stale_after: 1s, degrade_after: 100";
  config.blocks = "  - { type: poll, device: 1, profile: sic184-v3, point: POS_ACT_REAL, period: 100ms, output: 1 }\n";
  start();
  ASSERT_TRUE(output_becomes(1, 45)) << diagnostics();
  ASSERT_EQ(sim->control("dead 1 on"), "ok");
  ASSERT_TRUE(daemon->wait_for_log("Timeout rtu")) << diagnostics();
  EXPECT_EQ(output(1), 45) << "the value did not stay after the first time-out";
  EXPECT_TRUE(output_becomes(1, 0x7FFF)) << diagnostics();
  EXPECT_TRUE(log_has(*daemon, "output 1 reads 0x7FFF")) << diagnostics();
  ASSERT_EQ(sim->control("dead 1 off"), "ok");
  EXPECT_TRUE(output_becomes(1, 45)) << diagnostics();
}

TEST_F(MasterTest, ADeadSlaveIsDegradedAndDoesNotStarveTheOthers) {
  simulate({"1=sic184-v3", "2=sic184-v2,dead", "3=stepper-driver"});
  config.master =
      "response_timeout: 50ms, retries: 1, degrade_after: 2, backoff: 500ms, backoff_max: 1s, "
      "devices: { 1: { profile: sic184-v3 }, 2: { profile: sic184-v2 }, 3: { profile: stepper-driver } }";
  config.blocks =
      "  - { type: poll, device: 1, point: STATUS, period: 100ms, output: 1 }\n"
      "  - { type: poll, device: 2, point: MOTOR_STATUS, period: 100ms, output: 2 }\n"
      "  - { type: poll, device: 3, point: SUBDIVISION, period: 100ms, output: 3 }\n";
  start();
  ASSERT_TRUE(daemon->wait_for_log("modbus master: device 2 degraded")) << diagnostics();
  ASSERT_TRUE(output_becomes(3, 8)) << diagnostics();
  ASSERT_EQ(sim->control("reset"), "ok");
  const auto count = [&](int device) { return std::stoul(sim->control("count " + std::to_string(device)).substr(6)); };
  // The others keep being polled while device 2 only gets probes. How many of each, at
  // what pace, is the scheduler's (MasterScheduler's unit tests with time points: a dead
  // device degraded and probed with back-off, probes only where they delay nobody): a
  // ratio of wall-clock counts here would measure the machine's load.
  ASSERT_TRUE(eventually([&] { return count(1) >= 10 && count(3) >= 10; }, 10000ms)) << diagnostics();
  EXPECT_TRUE(daemon->log().find("modbus master: device 2 answers again") == std::string::npos) << diagnostics();
  // Back from the dead: one answered probe makes it healthy again.
  ASSERT_EQ(sim->control("dead 2 off"), "ok");
  EXPECT_TRUE(daemon->wait_for_log("modbus master: device 2 answers again", 5000ms)) << diagnostics();
  EXPECT_TRUE(output_becomes(2, 4)) << diagnostics();
}

TEST_F(MasterTest, ReadsAreRetriedWritesAreNot) {
  simulate({"1=sic184-v3,dead"});
  config.master = "retries: 2, degrade_after: 100, response_timeout: 50ms";
  config.blocks =
      "  - { type: poll, device: 1, profile: sic184-v3, point: STATUS, period: 400ms, output: 1 }\n"
      "  - { type: send, device: 1, point: POWER, period: 400ms, source: X+0x00 }\n";
  start();
  ASSERT_TRUE(eventually([&] { return count_frames(sim->frames(), "01 06 03 EB 00 00 F9 BA") >= 3; })) << diagnostics();
  const auto frames = sim->frames();
  // Each period: the read three times in a row (one try, two retries), the write once.
  std::vector<std::string> sequence;
  for (const auto& f : frames) {
    if (f.rx) sequence.push_back(f.hex == "01 06 03 EB 00 00 F9 BA" ? "W" : f.hex == "01 03 03 EA 00 01 A5 BA" ? "R" : "?");
  }
  std::string text;
  for (const auto& s : sequence) text += s;
  EXPECT_EQ(text.substr(0, 12), "RRRWRRRWRRRW") << diagnostics();
}

TEST_F(MasterTest, MasterOverTcp) {
  sim = std::make_unique<SlaveSim>(dir, std::vector<std::string>{"1=sic184-v3", "2=stepper-driver"}, false, true);
  ASSERT_TRUE(sim->ready()) << sim->output();
  config.line = "master-tcp: 127.0.0.1:" + std::to_string(sim->tcp_port());
  config.blocks =
      "  - { type: poll, device: 1, profile: sic184-v3, point: POS_ACT_REAL, period: 100ms, output: 1 }\n"
      "  - { type: poll, device: 2, profile: stepper-driver, point: STEP_ANGLE, period: 100ms, output: 2 }\n"
      "  - { type: send, device: 2, point: SUBDIVISION, period: 100ms, source: W+0x00 }\n";
  start();
  EXPECT_TRUE(output_becomes(1, 45)) << diagnostics();
  EXPECT_TRUE(output_becomes(2, 18)) << diagnostics();
  ModbusClient client(config.modbus_port);
  ASSERT_TRUE(client.write(w_bank, 16));
  EXPECT_TRUE(eventually([&] { return sim->control("get 2 1") == "value 16"; })) << diagnostics();
  // The PDU is the seed's; the MBAP header carries the unit.
  EXPECT_TRUE(eventually([&] {
    for (const auto& f : sim->frames())
      if (f.rx && !f.rtu && f.hex.ends_with("00 00 00 06 01 03 04 24 00 02")) return true;
    return false;
  })) << diagnostics();
  EXPECT_TRUE(log_has(*daemon, "modbus master: tcp 127.0.0.1:")) << diagnostics();
}

TEST_F(MasterTest, AMissingTcpTargetOrUnitIsNoAnswer) {
  sim = std::make_unique<SlaveSim>(dir, std::vector<std::string>{"1=sic184-v3"}, false, true);
  ASSERT_TRUE(sim->ready()) << sim->output();
  const auto nobody = free_port();
  config.line = "master-tcp: 127.0.0.1:" + std::to_string(nobody);
  config.master = "degrade_after: 2, retries: 0";
  config.blocks = "  - { type: poll, device: 1, profile: sic184-v3, point: STATUS, period: 100ms, output: 1 }\n";
  start();
  EXPECT_TRUE(daemon->wait_for_log("modbus master: cannot connect to 127.0.0.1:" + std::to_string(nobody))) << diagnostics();
  EXPECT_TRUE(daemon->wait_for_log("modbus master: Timeout tcp:127.0.0.1:" + std::to_string(nobody))) << diagnostics();
  EXPECT_TRUE(daemon->wait_for_log("modbus master: device 1 degraded")) << diagnostics();
  ASSERT_TRUE(daemon->terminate());

  // A unit the gateway does not know: exception 0x0B, Err04, and the device counts as silent.
  config.line = "master-tcp: 127.0.0.1:" + std::to_string(sim->tcp_port());
  config.blocks = "  - { type: poll, device: 9, register: 1002, function: 3, period: 100ms, output: 1 }\n";
  start();
  EXPECT_TRUE(daemon->wait_for_log(" -> 00 01 00 00 00 03 09 83 0B")) << diagnostics();
  EXPECT_TRUE(daemon->wait_for_log("modbus master: device 9 degraded")) << diagnostics();
  EXPECT_EQ(output(1), 0x7FFF);
}

TEST_F(MasterTest, ANewConfigOnSighupChangesThePlan) {
  simulate({"1=sic184-v3"});
  config.blocks = "  - { type: poll, device: 1, profile: sic184-v3, point: STATUS, period: 100ms, output: 1 }\n";
  start();
  ASSERT_TRUE(output_becomes(1, 1)) << diagnostics();
  config.blocks = "  - { type: poll, device: 1, profile: sic184-v3, point: POWER, period: 100ms, output: 1 }\n";
  daemon->rewrite_config(config.yaml());
  daemon->signal(SIGHUP);
  ASSERT_TRUE(daemon->wait_for_log("reloaded")) << diagnostics();
  EXPECT_TRUE(output_becomes(1, 80)) << diagnostics();
  EXPECT_TRUE(daemon->running());
}

// The reload's rollback: the new TCP listener was bound and the master's new line cannot
// open, so the plan is dropped — the new port closes again and the old one serves on.
TEST_F(MasterTest, AReloadWhoseLineCannotOpenKeepsTheOldPortAndPlan) {
  simulate({"1=sic184-v3"});
  config.blocks = "  - { type: poll, device: 1, profile: sic184-v3, point: STATUS, period: 100ms, output: 1 }\n";
  start();
  ASSERT_TRUE(output_becomes(1, 1)) << diagnostics();
  const auto old_port = config.modbus_port;
  auto next = config;
  next.modbus_port = free_port();
  next.line = "rtu: { device: " + (dir.path() / "no-such-tty").string() + ", baud: 9600 }";
  daemon->rewrite_config(next.yaml());
  daemon->signal(SIGHUP);
  ASSERT_TRUE(daemon->wait_for_log("reload failed")) << diagnostics();
  EXPECT_TRUE(wait_for_port(old_port)) << diagnostics();
  ModbusClient fresh(old_port);
  EXPECT_TRUE(fresh.read_input(online_bits, 1)) << diagnostics();
  EXPECT_FALSE(wait_for_port(next.modbus_port, 200ms)) << diagnostics();
  const auto polls = sim->frames().size();
  EXPECT_TRUE(eventually([&] { return sim->frames().size() > polls; })) << diagnostics();  // the old plan polls on
}

TEST_F(MasterTest, AMissingSerialDeviceStopsTheStartWithAClearError) {
  config.line = "rtu: { device: " + (dir.path() / "no-such-tty").string() + ", baud: 9600 }";
  config.blocks = "  - { type: poll, device: 1, register: 0, function: 3, period: 1s, output: 1 }\n";
  daemon = std::make_unique<Daemon>(dir, config.yaml());
  ASSERT_TRUE(eventually([&] { return !daemon->running(); })) << diagnostics();
  EXPECT_EQ(daemon->exit_code(), 1);
  EXPECT_TRUE(log_has(*daemon, "modbus master: " + (dir.path() / "no-such-tty").string() + ": cannot open")) << diagnostics();
}

TEST_F(MasterTest, CheckPrintsTheMergePlanAndTheBusLoad) {
  config.line = "rtu: { device: /dev/ttyUSB0, baud: 9600 }";
  config.master = "merge_gap: 2";
  config.blocks =
      "  - { type: poll, device: 1, profile: sic184-v3, point: POS_ACT_INT, period: 500ms, output: 1 }\n"
      "  - { type: poll, device: 1, point: VEL_ACT_INT, period: 1s, output: 2 }\n"
      "  - { type: poll, device: 3, profile: stepper-driver, point: STEP_ANGLE, period: 10ms, output: 3 }\n"
      "  - { type: send, device: 1, point: OUT2, period: 1s, source: X.0 }\n";
  const auto path = dir.path() / "check.yaml";
  std::ofstream(path) << config.yaml();
  const auto [status, output] = run(std::string(UNIMA_BRIDGE_CLI) + " check --config " + path.string());
  EXPECT_EQ(status, 0) << output;
  EXPECT_NE(output.find("master: rtu /dev/ttyUSB0 9600 baud, 10 bits per character, t3.5 = 3646 us"), std::string::npos) << output;
  EXPECT_NE(output.find("request  1: device   1, function  3, 1020..1025 (6 registers, spans a gap), every 500ms"),
            std::string::npos) << output;
  EXPECT_NE(output.find("      POS_ACT_INT dint -> output 1 (every 500ms, "), std::string::npos) << output;
  EXPECT_NE(output.find("      VEL_ACT_INT dint -> output 2 (every 1s, "), std::string::npos) << output;
  EXPECT_NE(output.find("request  2: device   1, function  5, 6001 (1 bit), every 1s"), std::string::npos) << output;
  EXPECT_NE(output.find("bus load: 103.0 requests/s"), std::string::npos) << output;
  EXPECT_NE(output.find("warning: device 3 is asked 100.0 times per second but takes at most 28.6"), std::string::npos)
      << output;
  EXPECT_NE(output.find("warning: the plan needs more than the line can carry"), std::string::npos) << output;
}

TEST(MasterCheck, AcceptsTheMasterExample) {
  const auto [status, output] = run(std::string(UNIMA_BRIDGE_CLI) + " check --config " UNIMA_SOURCE_DIR
                                    "/config/examples/master.yaml");
  EXPECT_EQ(status, 0) << output;
  EXPECT_NE(output.find("master: rtu /dev/ttyUSB0 38400 baud"), std::string::npos) << output;
  // The one warning a machine without the adapter gives: the example's line is not there.
  const auto device_warning = output.find("warning: modbus.rtu.device: /dev/ttyUSB0: ");
  const auto first_warning = output.find("warning");
  EXPECT_TRUE(first_warning == std::string::npos ||
              (first_warning == device_warning && output.find("warning", device_warning + 1) == std::string::npos))
      << output;
}

// SPEC §9: the foreign slaves' serial defaults and reply times, checked against the config.
TEST(MasterCheck, WarnsWhereTheConfigContradictsAPolledDevicesProfile) {
  TempDir dir;
  const auto file = dir.path() / "bridge.yaml";
  test_support::write_file(file,
                           "modbus:\n"
                           "  mode: master\n"
                           "  rtu: { device: /dev/ttyUSB0, baud: 19200 }\n"
                           "  master: { response_timeout: 20ms }\n"
                           "blocks:\n"
                           "  - { type: poll, device: 3, profile: stepper-driver, point: STEP_ANGLE, period: 1s, output: 1 }\n");
  const auto [status, output] = run(std::string(UNIMA_BRIDGE_CLI) + " check --config " + file.string());
  EXPECT_EQ(status, 0) << output;  // warnings, not errors
  EXPECT_NE(output.find(file.string() + ":3:8: warning: modbus.rtu is 19200 baud 8N1, but device 3 "
                        "(stepper-driver at " + file.string() + ":6:5) talks at 9600 baud 8N1 by default (seed 002)"),
            std::string::npos)
      << output;
  EXPECT_NE(output.find("takes at least 35 ms to answer (seed 002), but its response time-out is 20 ms"),
            std::string::npos)
      << output;
}

}  // namespace
}  // namespace unima::test
