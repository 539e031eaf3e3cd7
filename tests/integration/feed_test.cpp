// The feed transport of the real daemon (SPEC §6): snapshot on connect, telegrams into
// D_N and S_N, malformed lines answered and dropped, changes published, presence.

#include <thread>

#include "tests/integration/bridge_fixture.hpp"

namespace unima::test {
namespace {

class Feed : public BridgeTest {};

// SPEC §6, §10: W and X registers no master has written are no setpoints and are left
// out; C+0x00..0x12 are always there.
TEST_F(Feed, SnapshotOnConnectListsTheWrittenWAndXAndAllOfC) {
  start();
  auto feed = Socket::tcp(config.feed_port);
  std::vector<std::string> lines;
  for (int i = 0; i < 19; ++i) {
    auto line = feed.read_line();
    ASSERT_TRUE(line) << "after " << i << " lines";
    lines.push_back(*line);
  }
  EXPECT_EQ(lines[0], R"({"bank":"C","offset":0,"value":32767})");
  EXPECT_EQ(lines[18], R"({"bank":"C","offset":18,"value":0})");
  ModbusClient client(config.modbus_port);
  ASSERT_TRUE(client.write(0x0102, 0x7FFF));  // a master's 0x7FFF is a value it wrote
  ASSERT_TRUE(client.write(0x3010, 0));
  auto second = Socket::tcp(config.feed_port);
  EXPECT_EQ(second.read_line(), R"({"bank":"W","offset":2,"value":32767})");
  EXPECT_EQ(second.read_line(), R"({"bank":"X","offset":0,"value":0})");
  EXPECT_EQ(second.read_line(), R"({"bank":"C","offset":0,"value":32767})");
}

TEST_F(Feed, SnapshotCarriesWhatWasWrittenBefore) {
  start();
  ModbusClient client(config.modbus_port);
  ASSERT_TRUE(client.write(0x0103, 1234));
  auto feed = Socket::tcp(config.feed_port);
  EXPECT_TRUE(feed.wait_for_line(R"({"bank":"W","offset":3,"value":1234})"));
}

TEST_F(Feed, MalformedLinesAreAnsweredAndTheConnectionStays) {
  start();
  auto feed = feed_client();
  feed.send(std::string("this is not json\n"));
  auto answer = feed.read_line();
  ASSERT_TRUE(answer);
  EXPECT_TRUE(answer->starts_with(R"({"error":"not JSON)")) << *answer;
  feed.send(std::string(R"({"addr":5,"slot":0,"offset":0,"values":[70000]})") + "\n");
  answer = feed.read_line();
  ASSERT_TRUE(answer);
  EXPECT_EQ(*answer, R"({"error":"value 70000 is outside -32768..65535"})");
  feed.send(std::string(R"({"addr":5,"slot":0,"offset":62,"values":[1,2,3]})") + "\n");
  answer = feed.read_line();
  ASSERT_TRUE(answer);
  EXPECT_TRUE(answer->find("run past the end of bank D1") != std::string::npos) << *answer;
  // Still connected, and the next good line is applied.
  feed_and_wait(feed, R"({"addr":5,"slot":0,"offset":5,"values":[321]})", 0x0011 + 5, 321);
}

// Issue 30 point 5: a NUL byte after a telegram's JSON makes the line malformed (SPEC §6):
// it is answered {"error":…} and changes nothing. White space after the JSON is fine.
TEST_F(Feed, ANulByteAfterTheJsonIsAnsweredWithAnErrorAndChangesNothing) {
  start();
  auto feed = feed_client();
  feed_and_wait(feed, R"({"addr":5,"slot":0,"offset":1,"values":[321]})", 0x0011 + 1, 321);
  feed.send(std::string(R"({"addr":5,"slot":0,"offset":1,"values":[1]})") + '\0' + "garbage\n");
  const auto answer = feed.read_line();
  ASSERT_TRUE(answer) << "no answer to the line with a NUL byte";
  EXPECT_TRUE(answer->starts_with(R"({"error":"not JSON: a NUL byte)")) << *answer;
  // The next line, with white space after its JSON, is applied; the one with the NUL never was.
  feed_and_wait(feed, R"({"addr":5,"slot":0,"offset":2,"values":[654]} )" "\t", 0x0011 + 2, 654);
  ModbusClient client(config.modbus_port);
  EXPECT_EQ(client.read_input(0x0011 + 1, 1), std::vector<std::uint16_t>{321});
}

TEST_F(Feed, TelegramsOfIoModulesGoToTheirSlotBank) {
  start();
  auto feed = feed_client();
  // S2 at its default base 0x2200; slot 2 at the bridge's own address 5.
  feed_and_wait(feed, R"({"addr":5,"slot":2,"offset":3,"values":[11,12]})", 0x2204, 12);
  ModbusClient client(config.modbus_port);
  const auto online = client.read_input(0x1033, 1);
  ASSERT_TRUE(online);
  EXPECT_EQ((*online)[0] & 0x0200, 0x0200);  // bit 9 = S2
  EXPECT_EQ(client.read_input(0x2200, 1), std::vector<std::uint16_t>{0x7FFF});  // never carried
}

TEST_F(Feed, TelegramsOfOtherDevicesAreIgnored) {
  start();
  auto feed = feed_client();
  feed.send(std::string(R"({"addr":9,"slot":0,"offset":0,"values":[1]})") + "\n");
  feed_and_wait(feed, R"({"addr":5,"slot":0,"offset":0,"values":[2]})", 0x0011, 2);
  ModbusClient client(config.modbus_port);
  const auto online = client.read_input(0x1033, 1);
  ASSERT_TRUE(online);
  EXPECT_EQ((*online)[0], 0x0001);
}

// Seed §3.2.1: a unit's control system, its speed regulator and voltage regulator all sit
// at the unit's address; each D_N is chosen by type and address (SPEC §6).
TEST_F(Feed, AUnitsComponentsAtOneAddressEachFillTheirOwnBank) {
  config.banks = "{ D1: 0x0011, D2: 0x0111, W: 0x0100 }";
  config.devices = "{ D1: { type: unigen-chp, address: 5 }, D2: { type: usc, address: 5 } }";
  start();
  auto feed = feed_client();
  feed_and_wait(feed, R"({"addr":5,"slot":0,"device":"usc","offset":3,"values":[1500]})", 0x0111 + 3, 1500);
  ModbusClient client(config.modbus_port);
  EXPECT_EQ(client.read_input(0x0011 + 3, 1), std::vector<std::uint16_t>{0x7FFF});  // the CHP heard nothing
  EXPECT_EQ(client.read_input(0x1033, 1), std::vector<std::uint16_t>{0x0002});     // only D2 on-line

  // Not naming the component is ambiguous here: answered, applied to neither.
  feed.send(std::string(R"({"addr":5,"slot":0,"offset":3,"values":[999]})") + "\n");
  const auto answer = feed.read_line();
  ASSERT_TRUE(answer);
  EXPECT_TRUE(answer->starts_with(R"({"error":"address 5 holds D1 (unigen-chp), D2 (usc))")) << *answer;
  EXPECT_EQ(client.read_input(0x0111 + 3, 1), std::vector<std::uint16_t>{1500});

  feed_and_wait(feed, R"({"addr":5,"slot":0,"device":"microgen-chp","offset":3,"values":[42]})", 0x0011 + 3, 42);
  EXPECT_EQ(client.read_input(0x0111 + 3, 1), std::vector<std::uint16_t>{1500});
  EXPECT_EQ(client.read_input(0x1033, 1), std::vector<std::uint16_t>{0x0003});
  // A component that is not configured at the address is another device's: no answer.
  feed.send(std::string(R"({"addr":5,"slot":0,"device":"uvr","offset":0,"values":[1]})") + "\n");
  feed_and_wait(feed, R"({"addr":5,"slot":0,"device":"usc","offset":3,"values":[1501]})", 0x0111 + 3, 1501);
}

TEST_F(Feed, EachComponentGoesOffLineOnItsOwn) {
  config.unimabus_extra = "  offline_after: 400ms\n";
  config.banks = "{ D1: 0x0011, D2: 0x0111, W: 0x0100 }";
  config.devices = "{ D1: { type: unigen-chp, address: 5 }, D2: { type: uvr, address: 5 } }";
  start();
  auto feed = feed_client();
  ModbusClient client(config.modbus_port);
  // Keep the UVR talking while the CHP controller falls silent.
  bool chp_went_offline = false;
  for (int i = 0; i < 40 && !chp_went_offline; ++i) {
    if (i == 0) feed.send(std::string(R"({"addr":5,"slot":0,"device":"unigen-chp","offset":1,"values":[1500]})") + "\n");
    feed.send(std::string(R"({"addr":5,"slot":0,"device":"uvr","offset":0,"values":[7]})") + "\n");
    std::this_thread::sleep_for(std::chrono::milliseconds(100));  // the UVR's pace: well within offline_after
    const auto online = client.read_input(0x1033, 1);
    ASSERT_TRUE(online);
    chp_went_offline = i > 0 && (*online)[0] == 0x0002;
  }
  EXPECT_TRUE(chp_went_offline) << daemon->log();
  EXPECT_TRUE(daemon->wait_for_log("D1 (unigen-chp at UnimaBUS address 5) off-line"));
  EXPECT_EQ(client.read_input(0x0012, 1), std::vector<std::uint16_t>{0x7FFF});
}

// SPEC §6 limits: at most unimabus.max_clients feed connections; more are told so and
// closed, logged once per episode with a count, and Modbus serves on.
TEST_F(Feed, ClientsBeyondTheLimitAreToldSoAndClosed) {
  config.unimabus_extra = "  max_clients: 2\n";
  start();
  auto first = feed_client();
  auto second = feed_client();
  for (int i = 0; i < 5; ++i) {
    auto refused = Socket::tcp(config.feed_port);
    const auto answer = refused.read_line();
    ASSERT_TRUE(answer) << daemon->log();
    EXPECT_EQ(*answer, R"x({"error":"too many feed clients (2 connected)"})x");
    EXPECT_TRUE(refused.closed_by_peer());
  }
  ModbusClient client(config.modbus_port);
  EXPECT_TRUE(client.read_input(0x0011, 1));
  EXPECT_EQ(daemon->log_count("refusing"), 1u) << daemon->log();
  // One leaves: the next is served with its snapshot, and the log says how many were refused.
  first.close();
  EXPECT_TRUE(daemon->wait_for_log("accepting clients again (5 refused meanwhile)")) << daemon->log();
  auto third = feed_client();
  feed_and_wait(third, R"({"addr":5,"slot":0,"offset":5,"values":[77]})", 0x0011 + 5, 77);
}

// The issue's flood: 300 feed connections against a daemon allowed 256 descriptors. The feed
// holds at most max_clients of them, so the Modbus side always has descriptors to accept
// and answer with, and the feed clients that were taken get their snapshot.
TEST_F(Feed, ThreeHundredFeedConnectionsAtTwoHundredFiftySixDescriptorsLeaveModbusAnswering) {
  daemon = start_with_few_descriptors(dir, config.yaml(), config.modbus_port, 256);
  auto feeds = tcp_clients(config.feed_port, 300);
  ASSERT_TRUE(daemon->wait_for_log("feed: refusing")) << daemon->log().substr(0, 2000);
  for (int i = 0; i < 20; ++i) {
    ModbusClient client(config.modbus_port);
    ASSERT_TRUE(client.read_input(0x0011, 1)) << "connection " << i << "\n" << daemon->log().substr(0, 2000);
  }
  EXPECT_TRUE(feeds.front().wait_for_line(R"({"bank":"C","offset":18,"value":0})")) << daemon->log().substr(0, 2000);
  EXPECT_EQ(daemon->log().find("accept failed"), std::string::npos) << daemon->log().substr(0, 2000);
}

// Feed clients that never read while W changes fast: each is dropped once 1 MiB is queued
// for it, so the daemon's memory stays bounded by max_clients × (1 MiB queued + 1 MiB
// being written), not by how long they stay.
TEST_F(Feed, ClientsThatNeverReadAreDroppedBeforeTheyCostMoreThanTheirQueue) {
  config.extra = "state: { file: none }\n";  // as fast as W can change
  start();
  const auto before = resident_set(daemon->pid());
  auto idle_readers = tcp_clients(config.feed_port, 50);
  ModbusClient writer(config.modbus_port);
  std::vector<std::uint16_t> values(16);
  const auto until = std::chrono::steady_clock::now() + 20s;
  // Bounded in time and count. The 16 readers get the same lines, so they fill up alike:
  // a quarter more writes after the first is dropped drops the others too.
  int writes = 0, first_dropped_at = 0;
  while (std::chrono::steady_clock::now() < until && writes < 100000) {
    for (auto& v : values) v = static_cast<std::uint16_t>(v + 1);
    ASSERT_TRUE(writer.write_many(0x0100, values)) << daemon->log().substr(0, 2000);
    ++writes;
    if (first_dropped_at == 0 && writes % 256 == 0 && daemon->log_count("is not reading") > 0) first_dropped_at = writes;
    if (first_dropped_at > 0 && writes > first_dropped_at + first_dropped_at / 4) break;
  }
  EXPECT_TRUE(daemon->wait_for_log("is not reading")) << daemon->log().substr(0, 2000);
  const auto after = resident_set(daemon->pid());
  constexpr long max_clients = 16, per_client_kib = 2 * 1024, slack_kib = 16 * 1024;
  EXPECT_LE(after.peak_kib - before.now_kib, max_clients * per_client_kib + slack_kib)
      << "peak " << after.peak_kib << " KiB, " << before.now_kib << " KiB before";
  // A reader that comes now is served at once.
  idle_readers.clear();
  auto fresh = feed_client();
  feed_and_wait(fresh, R"({"addr":5,"slot":0,"offset":5,"values":[77]})", 0x0011 + 5, 77);
}

// Whatever a line holds, it is answered and never stops the daemon; the log gets the first
// malformed line of a client, escaped, and the count when the client leaves.
TEST_F(Feed, MalformedLinesAreAnsweredLoggedOnceAndEscaped) {
  start();
  auto feed = feed_client();
  feed.send(std::string(R"({"addr":5,"slot":0,"offset":0,"values":[1e400]})") + "\n");
  auto answer = feed.read_line();
  ASSERT_TRUE(answer) << daemon->log();
  EXPECT_TRUE(answer->starts_with(R"({"error":)")) << *answer;
  feed.send(std::string("{\"a\\nFORGED log line\":1}\n"));  // a key holding a newline
  answer = feed.read_line();
  ASSERT_TRUE(answer);
  EXPECT_TRUE(answer->find("unknown field") != std::string::npos) << *answer;
  for (int i = 0; i < 20; ++i) feed.send(std::string("not json\n"));
  for (int i = 0; i < 20; ++i) ASSERT_TRUE(feed.read_line());
  feed_and_wait(feed, R"({"addr":5,"slot":0,"offset":5,"values":[78]})", 0x0011 + 5, 78);
  EXPECT_EQ(daemon->log_count("sent a malformed line"), 1u) << daemon->log();
  feed.close();
  EXPECT_TRUE(daemon->wait_for_log("(22 malformed lines, the first one logged)")) << daemon->log();
  EXPECT_EQ(daemon->log().find("\nFORGED"), std::string::npos);
  EXPECT_TRUE(daemon->running());
}

TEST_F(Feed, SilentDevicesGoOffLine) {
  config.unimabus_extra = "  offline_after: 300ms\n";
  start();
  auto feed = feed_client();
  // +0x00 is the status bit field, +0x01 the engine speed (analog).
  feed_and_wait(feed, R"({"addr":5,"slot":0,"offset":0,"values":[80,1500]})", 0x0012, 1500);
  ModbusClient client(config.modbus_port);
  ASSERT_TRUE(eventually([&] {
    const auto v = client.read_input(0x0011, 2);
    return v == std::vector<std::uint16_t>{0, 0x7FFF};
  })) << daemon->log();
  const auto online = client.read_input(0x1033, 1);
  ASSERT_TRUE(online);
  EXPECT_EQ((*online)[0] & 0x0001, 0);
  EXPECT_TRUE(daemon->wait_for_log("D1 (unigen-chp at UnimaBUS address 5) off-line"));
  // Heard again: on-line with the value it carries.
  feed_and_wait(feed, R"({"addr":5,"slot":0,"offset":1,"values":[1501]})", 0x0012, 1501);
}

TEST_F(Feed, BitRegistersOfAnOffLineDeviceReadZero) {
  start();
  ModbusClient client(config.modbus_port);
  // unigen-chp +0x10 are user binary inputs (bits), +0x01 engine speed (analog).
  EXPECT_EQ(client.read_input(0x0011 + 0x10, 1), std::vector<std::uint16_t>{0});
  EXPECT_EQ(client.read_input(0x0011 + 0x01, 1), std::vector<std::uint16_t>{0x7FFF});
}

TEST_F(Feed, EveryFeedClientGetsEveryChange) {
  start();
  auto first = feed_client();
  auto second = feed_client();
  ModbusClient client(config.modbus_port);
  ASSERT_TRUE(client.write(0x3010, 0x0005));
  EXPECT_TRUE(first.wait_for_line(R"({"bank":"X","offset":0,"value":5})"));
  EXPECT_TRUE(second.wait_for_line(R"({"bank":"X","offset":0,"value":5})"));
}

TEST_F(Feed, OutOfDescriptorsTheFeedWaitsInsteadOfSpinningAndRecovers) {
  config.unimabus_extra = "  max_clients: 1000\n";  // above the descriptors, so accept fails first
  daemon = start_with_few_descriptors(dir, config.yaml(), config.modbus_port);
  auto clients = tcp_clients(config.feed_port, 40);
  std::string report;
  EXPECT_TRUE(daemon->logs_slowly("feed: accept failed", report)) << report;
  clients.clear();
  EXPECT_TRUE(eventually([&] {
    auto feed = Socket::tcp(config.feed_port);
    return feed.valid() && feed.wait_for_line(R"({"bank":"C","offset":18,"value":0})", 1000ms);
  })) << daemon->log().substr(0, 2000);
}

TEST_F(Feed, UnixSocketFeed) {
  config.feed_listen = "unix:" + (dir.path() / "feed.sock").string();
  start();
  ASSERT_TRUE(eventually([&] { return Socket::unix_socket(config.feed_listen.substr(5)).valid(); }));
  auto feed = feed_client();
  feed_and_wait(feed, R"({"addr":5,"slot":0,"offset":1,"values":[1500]})", 0x0012, 1500);
}

}  // namespace
}  // namespace unima::test
