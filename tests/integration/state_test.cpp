// The state file of the real daemon (SPEC §10): what a master wrote and had acknowledged
// is back after kill -9, at any instant; unset registers stay out of the feed snapshot; a
// corrupt file — foreign, or damaged anywhere — is kept aside, nothing of it is restored,
// and it never stops the start; a write the file's disk refuses changes nothing (not the
// registers, not UnimaBUS) and is answered exception 04 (issue 29, rows 2 and 4).

#include <modbus/modbus.h>
#include <signal.h>

#include <atomic>
#include <random>
#include <sstream>
#include <thread>

#include "tests/integration/bridge_fixture.hpp"
#include "state/state_journal.hpp"
#include "tests/integration/state_outage.hpp"

namespace unima::test {
namespace {

constexpr int w_base = 0x0100;  // the tests' layout: W at 0x0100, X at its default 0x3010
constexpr int x_address = 0x3010;

class State : public BridgeTest {
 protected:
  std::filesystem::path state_file() const { return dir.path() / "bridge.state"; }
  void kill_and_restart() {
    daemon->signal(SIGKILL);
    ASSERT_TRUE(eventually([&] { return !daemon->running(); }));
    daemon.reset();
    start();
  }
  std::vector<std::uint16_t> read_w() {
    ModbusClient client(config.modbus_port);
    const auto values = client.read_input(w_base, 16);
    EXPECT_TRUE(values);
    return values.value_or(std::vector<std::uint16_t>(16));
  }
};

TEST_F(State, AcknowledgedWritesToWXAndAWriteBlockAreBackAfterKill9) {
  config.blocks = "  - { type: write, register: 0x0201, output: 3 }\n";
  start();
  {
    ModbusClient client(config.modbus_port);
    ASSERT_TRUE(client.write(w_base + 3, 1234));
    ASSERT_TRUE(client.write_many(w_base + 10, {7, 8, 9}));
    ASSERT_TRUE(client.write(x_address, 0x0005));
    ASSERT_TRUE(client.write(0x0201, 4321));          // the write block: user output 3 = C+2
  }
  const auto status = run(std::string(UNIMA_BRIDGE_CLI) + " status --socket " + config.status_socket);
  EXPECT_NE(status.output.find("State       " + state_file().string() + ": 6 values recorded in "), std::string::npos)
      << status.output;
  kill_and_restart();
  const auto w = read_w();
  EXPECT_EQ(w[3], 1234);
  EXPECT_EQ(w[10], 7);
  EXPECT_EQ(w[12], 9);
  EXPECT_EQ(w[0], 0x7FFF);  // never written
  ModbusClient client(config.modbus_port);
  EXPECT_EQ(client.read_input(x_address, 1), std::vector<std::uint16_t>{5});
  // The first snapshot carries what came back, and nothing a master never wrote.
  auto feed = Socket::tcp(config.feed_port);
  EXPECT_EQ(feed.read_line(), R"({"bank":"W","offset":3,"value":1234})");
  EXPECT_EQ(feed.read_line(), R"({"bank":"W","offset":10,"value":7})");
  EXPECT_EQ(feed.read_line(), R"({"bank":"W","offset":11,"value":8})");
  EXPECT_EQ(feed.read_line(), R"({"bank":"W","offset":12,"value":9})");
  EXPECT_EQ(feed.read_line(), R"({"bank":"X","offset":0,"value":5})");
  EXPECT_EQ(feed.read_line(), R"({"bank":"C","offset":0,"value":32767})");
  EXPECT_EQ(feed.read_line(), R"({"bank":"C","offset":1,"value":32767})");
  EXPECT_EQ(feed.read_line(), R"({"bank":"C","offset":2,"value":4321})");
  EXPECT_TRUE(daemon->wait_for_log("holds 6 values")) << daemon->log();
}

// The issue's test: SIGKILL at random instants of a stream of writes; after each restart
// every register holds the last value acknowledged for it, or the one write that was on
// its way (sent, not yet answered), and the file always loads.
TEST_F(State, KilledAtRandomInstantsDuringWritesEveryAcknowledgedValueIsBack) {
  start();
  std::mt19937 random(20261124);
  std::vector<std::uint16_t> acknowledged(16, 0x7FFF);
  std::uint16_t next_value = 1;
  for (int round = 0; round < 12; ++round) {
    std::atomic<bool> stop = false;
    std::vector<std::optional<std::uint16_t>> in_flight(16);
    std::thread writer([&] {
      ModbusClient client(config.modbus_port);
      for (int i = 0; i < 100000 && !stop; ++i) {
        const int offset = static_cast<int>(next_value % 16);
        const std::uint16_t value = next_value++;
        in_flight[offset] = value;
        if (!client.write(w_base + offset, value)) return;  // the daemon is gone
        acknowledged[offset] = value;
        in_flight[offset].reset();
      }
    });
    // The instant of the kill is what the test varies.
    std::this_thread::sleep_for(std::chrono::milliseconds(std::uniform_int_distribution(5, 120)(random)));
    daemon->signal(SIGKILL);
    stop = true;
    writer.join();
    ASSERT_TRUE(eventually([&] { return !daemon->running(); }));
    daemon.reset();
    start();
    ASSERT_EQ(daemon->log().find("kept aside"), std::string::npos) << daemon->log();
    const auto w = read_w();
    for (int r = 0; r < 16; ++r)
      EXPECT_TRUE(w[r] == acknowledged[r] || (in_flight[r] && w[r] == *in_flight[r]))
          << "round " << round << ", W+" << r << " reads " << w[r] << ", acknowledged " << acknowledged[r];
    acknowledged = w;  // a write that was on its way may or may not have stayed: now it is known
  }
  EXPECT_GT(next_value, 12) << "the writes never started";
}

// The order on the wire of system calls: a write's answer (sendto) leaves only after an
// fdatasync that followed it. Counted from the daemon's start, the k-th answer has at least
// k more completed fdatasync calls before it than there were when the writes began.
TEST_F(State, TheAnswerToAWriteLeavesOnlyAfterItsFdatasync) {
  const auto trace = dir.path() / "strace.txt";
  daemon = std::make_unique<Daemon>(dir, config.yaml(), std::vector<std::string>{"UNIMA_TEST_STRACE=" + trace.string()});
  ASSERT_TRUE(wait_for_port(config.modbus_port)) << daemon->log();
  const auto completed_syncs = [](const std::string& text) {
    std::size_t count = 0;
    std::istringstream lines(text);
    for (std::string line; std::getline(lines, line);)
      if (line.find("fdatasync") != std::string::npos && line.ends_with("= 0")) ++count;
    return count;
  };
  ASSERT_TRUE(eventually([&] { return completed_syncs(read_file(trace)) > 0; })) << read_file(trace);
  const auto before = completed_syncs(read_file(trace));
  {
    ModbusClient client(config.modbus_port);
    for (int k = 0; k < 3; ++k) ASSERT_TRUE(client.write(w_base + k, static_cast<std::uint16_t>(100 + k)));
  }
  std::vector<std::size_t> syncs_before_answer;
  ASSERT_TRUE(eventually([&] {
    syncs_before_answer.clear();
    std::size_t syncs = 0;
    std::istringstream lines(read_file(trace));
    for (std::string line; std::getline(lines, line);) {
      if (line.find("fdatasync") != std::string::npos && line.ends_with("= 0")) ++syncs;
      if (line.find("sendto(") != std::string::npos && line.find(", 12, ") != std::string::npos)
        syncs_before_answer.push_back(syncs);
    }
    return syncs_before_answer.size() == 3;
  })) << read_file(trace);
  for (std::size_t k = 0; k < 3; ++k) EXPECT_GE(syncs_before_answer[k], before + k + 1) << read_file(trace);
}

// A write takes effect only once the state file holds it; a read pipelined behind it on
// the same connection, in the same segment, still sees what it wrote, and the answers
// keep their order.
TEST_F(State, AReadPipelinedBehindAWriteSeesWhatItWrote) {
  start();
  auto socket = Socket::tcp(config.modbus_port);
  const Bytes write_then_read = {0x00, 0x01, 0x00, 0x00, 0x00, 0x06, 0x01, 0x06, 0x01, 0x00, 0x12, 0x34,   // W+0 = 0x1234
                                 0x00, 0x02, 0x00, 0x00, 0x00, 0x06, 0x01, 0x04, 0x01, 0x00, 0x00, 0x01};  // read W+0
  socket.send(write_then_read);
  EXPECT_EQ(socket.receive(12 + 11), (Bytes{0x00, 0x01, 0x00, 0x00, 0x00, 0x06, 0x01, 0x06, 0x01, 0x00, 0x12, 0x34,
                                            0x00, 0x02, 0x00, 0x00, 0x00, 0x05, 0x01, 0x04, 0x02, 0x12, 0x34}));
}

TEST_F(State, ACorruptFileIsKeptAsideAndTheDaemonStartsWithNothingSet) {
  test_support::write_file(state_file(), "this is not a state file\n");
  start();
  EXPECT_TRUE(daemon->wait_for_log("not a unima-bridge state file: kept aside as")) << daemon->log();
  bool aside = false;
  for (const auto& entry : std::filesystem::directory_iterator(dir.path()))
    aside |= entry.path().filename().string().starts_with("bridge.state.corrupt-") &&
             read_file(entry.path()) == "this is not a state file\n";
  EXPECT_TRUE(aside);
  EXPECT_EQ(read_w()[0], 0x7FFF);
  ModbusClient client(config.modbus_port);
  ASSERT_TRUE(client.write(w_base, 42));
  kill_and_restart();
  EXPECT_EQ(read_w()[0], 42);
}

// A last record whose checksum holds but which names no register (W has 0..15) is no
// write a crash cut short: the file is not the daemon's to trust, and is kept aside like
// any other damage (issue 43, finding 13).
TEST_F(State, ALastRecordForNoRegisterIsDamageAndTheFileIsKeptAside) {
  const auto text = std::string(state::journal_header) + state::checked_line("W 0 300") + state::checked_line("W 16 5");
  test_support::write_file(state_file(), text);
  start();
  EXPECT_TRUE(daemon->wait_for_log("line 3: bad register or value: kept aside as")) << daemon->log();
  bool aside = false;
  for (const auto& entry : std::filesystem::directory_iterator(dir.path()))
    aside |= entry.path().filename().string().starts_with("bridge.state.corrupt-") && read_file(entry.path()) == text;
  EXPECT_TRUE(aside);
  EXPECT_EQ(read_w()[0], 0x7FFF) << "W+0 restored from a file with a forged record";
}

// Issue 29, row 4: W+0 was set to 200, then to 300 (acknowledged), and a record between
// them — or after them, with more after it — is damaged. Restoring what came before the
// damage would bring back 200 and publish it; SPEC §10 says: set the file aside, start
// with nothing set.
TEST_F(State, AFileDamagedInTheMiddleIsKeptAsideAndNothingOfItIsRestored) {
  for (const bool damage_between : {true, false}) {
    SCOPED_TRACE(damage_between ? "damage between 200 and 300" : "damage after 300, a record after it");
    // The records as the daemon writes them: a value's record from a write of W+0 alone.
    start();
    {
      ModbusClient client(config.modbus_port);
      ASSERT_TRUE(client.write(w_base, 200));
      ASSERT_TRUE(client.write(w_base, 300));
      ASSERT_TRUE(client.write(w_base + 1, 7));
    }
    daemon->signal(SIGKILL);
    ASSERT_TRUE(eventually([&] { return !daemon->running(); }));
    daemon.reset();
    auto text = read_file(state_file());
    const auto at_300 = text.find("W 0 300 ");
    const auto at_w1 = text.find("W 1 7 ");
    ASSERT_NE(at_300, std::string::npos) << text;
    ASSERT_NE(at_w1, std::string::npos) << text;
    text.insert(damage_between ? at_300 : at_w1, "W 0 250 00000000\n");
    test_support::write_file(state_file(), text);
    for (const auto& entry : std::filesystem::directory_iterator(dir.path()))
      if (entry.path().filename().string().starts_with("bridge.state.corrupt-")) std::filesystem::remove(entry.path());

    start();
    EXPECT_TRUE(daemon->wait_for_log("checksum mismatch: kept aside as")) << daemon->log();
    EXPECT_TRUE(daemon->wait_for_log("starting with no value set")) << daemon->log();
    bool aside = false;
    for (const auto& entry : std::filesystem::directory_iterator(dir.path()))
      aside |= entry.path().filename().string().starts_with("bridge.state.corrupt-") && read_file(entry.path()) == text;
    EXPECT_TRUE(aside);
    const auto w = read_w();
    EXPECT_EQ(w[0], 0x7FFF) << "W+0 restored from a damaged file";
    EXPECT_EQ(w[1], 0x7FFF);
    // Nothing of it is published: the snapshot has no W at all.
    auto feed = Socket::tcp(config.feed_port);
    const auto first = feed.read_line();
    ASSERT_TRUE(first);
    EXPECT_EQ(first->find(R"("bank":"W")"), std::string::npos) << *first;
    daemon->signal(SIGKILL);
    ASSERT_TRUE(eventually([&] { return !daemon->running(); }));
    daemon.reset();
    std::filesystem::remove(state_file());
  }
}

TEST_F(State, FileNoneKeepsNothing) {
  config.extra = "state: { file: none }\n";
  start();
  {
    ModbusClient client(config.modbus_port);
    ASSERT_TRUE(client.write(w_base + 1, 99));
  }
  kill_and_restart();
  EXPECT_EQ(read_w()[1], 0x7FFF);
  EXPECT_FALSE(std::filesystem::exists(state_file()));
}

// Its directory cannot be made: a regular file stands where it would go. (A directory that
// is merely not there is made, with a warning: config_messages_test.)
TEST_F(State, AStateFileThatCannotBeWrittenIsAStartUpErrorNamingIt) {
  test_support::write_file(dir.path() / "not-a-dir", "a file\n");
  const auto path = (dir.path() / "not-a-dir" / "state").string();
  config.extra = "state: { file: " + path + " }\n";
  daemon = std::make_unique<Daemon>(dir, config.yaml());
  ASSERT_TRUE(eventually([&] { return !daemon->running(); }));
  EXPECT_NE(daemon->exit_code(), 0);
  EXPECT_NE(daemon->log().find("state file " + path), std::string::npos) << daemon->log();
}

// A disk that refuses the state file's writes (issue 29, row 2): tests/integration/state_outage.hpp.
class StateOutage : public State {
 protected:
  void SetUp() override {
    State::SetUp();
    config.log_level = "warn";
    config.blocks = state_outage::write_blocks();
    start();
    last_round = state_outage::fill(config.modbus_port, w_base);
    kill_and_restart();
    ASSERT_EQ(read_w(), last_round);
    ASSERT_GT(std::filesystem::file_size(state_file()), std::filesystem::file_size(dir.path() / "daemon.log") + 400)
        << daemon->log();
  }
  void refuse_writes() const { state_outage::refuse_writes(*daemon, state_file()); }
  void take_writes() const { state_outage::take_writes(*daemon); }
  bool error_bit_set() {
    ModbusClient client(config.modbus_port);
    const auto c13 = client.read_input(0x1033, 1);  // C+0x13 at the default base
    return c13 && ((*c13)[0] & 0x8000) != 0;
  }
  std::vector<std::uint16_t> last_round;  // W+0..15 as SetUp left them, all set
};

// Row 2: the master gets exception 04, the register keeps its value, UnimaBUS gets nothing,
// the log and the Error bit say why; once the disk takes writes again the next write is
// taken, and it is the one a restart brings back.
TEST_F(StateOutage, AWriteTheDiskRefusesIsExceptionFourAndChangesNothing) {
  auto feed = feed_client();
  refuse_writes();
  {
    ModbusClient client(config.modbus_port);
    EXPECT_FALSE(client.write(w_base + 3, 54242));
    EXPECT_EQ(client.last_error(), EMBXSFAIL) << modbus_strerror(client.last_error()) << "\n" << daemon->log();
    // The same connection serves on.
    EXPECT_FALSE(client.write(w_base + 4, 54343));
    EXPECT_EQ(client.last_error(), EMBXSFAIL) << modbus_strerror(client.last_error());
    EXPECT_EQ(client.read_input(w_base, 16), last_round);
  }
  EXPECT_TRUE(daemon->wait_for_log("state: cannot write " + state_file().string())) << daemon->log();
  EXPECT_EQ(daemon->log_count("state: cannot write"), 1u) << daemon->log();  // once, not per write
  EXPECT_NE(daemon->log().find("writes are refused (exception 04)"), std::string::npos) << daemon->log();
  EXPECT_TRUE(error_bit_set());

  take_writes();
  {
    ModbusClient client(config.modbus_port);
    ASSERT_TRUE(client.write(w_base + 3, 5151)) << modbus_strerror(client.last_error()) << "\n" << daemon->log();
  }
  // UnimaBUS: the next line after the refusals is the write that was taken.
  EXPECT_EQ(feed.read_line(), R"({"bank":"W","offset":3,"value":5151})");
  kill_and_restart();
  auto expected = last_round;
  expected[3] = 5151;
  EXPECT_EQ(read_w(), expected);
}

// A write of several registers the disk refuses changes none of them.
TEST_F(StateOutage, AMultiRegisterWriteTheDiskRefusesChangesNoneOfItsRegisters) {
  auto feed = feed_client();
  refuse_writes();
  {
    ModbusClient client(config.modbus_port);
    EXPECT_FALSE(client.write_many(w_base + 2, {50001, 50002, 50003, 50004, 50005}));
    EXPECT_EQ(client.last_error(), EMBXSFAIL) << modbus_strerror(client.last_error()) << "\n" << daemon->log();
    EXPECT_EQ(client.read_input(w_base, 16), last_round);
  }
  take_writes();
  {
    ModbusClient client(config.modbus_port);
    ASSERT_TRUE(client.write(w_base + 15, 9)) << daemon->log();
  }
  EXPECT_EQ(feed.read_line(), R"({"bank":"W","offset":15,"value":9})");
  kill_and_restart();
  auto expected = last_round;
  expected[15] = 9;
  EXPECT_EQ(read_w(), expected);
}

}  // namespace
}  // namespace unima::test
