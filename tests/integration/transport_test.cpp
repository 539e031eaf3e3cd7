// The UnimaBUS transports other than the feed (SPEC §6), in the real daemon: the
// simulator, and a recording made by `record` played back by `replay`.

#include <algorithm>
#include <thread>

#include <nlohmann/json.hpp>

#include "tests/integration/bridge_fixture.hpp"
#include "unimabus/recording.hpp"

namespace unima::test {
namespace {

class Transport : public BridgeTest {};

TEST_F(Transport, TheSimulatorFillsEachComponentOfAUnit) {
  config.transport = "sim";
  config.unimabus_extra = "  sim: { period: 50ms }\n";
  config.banks = "{ D1: 0x0011, D2: 0x0111, D3: 0x0211, W: 0x0100 }";
  config.devices =
      "{ D1: { type: unigen-chp, address: 5 }, D2: { type: usc, address: 5 }, D3: { type: uvr, address: 5 } }";
  start();
  ModbusClient client(config.modbus_port);
  ASSERT_TRUE(eventually([&] { return client.read_input(0x1033, 1) == std::vector<std::uint16_t>{0x0007}; }))
      << daemon->log();
  // Each bank has its own values: the tables differ, so would their sims.
  const auto d1 = client.read_input(0x0011, 8);
  const auto d2 = client.read_input(0x0111, 8);
  const auto d3 = client.read_input(0x0211, 8);
  ASSERT_TRUE(d1 && d2 && d3);
  EXPECT_NE(*d1, *d2);
  EXPECT_NE(*d2, *d3);
}


std::vector<nlohmann::json> recorded_lines(const std::filesystem::path& file) {
  std::vector<nlohmann::json> lines;
  std::istringstream in(read_file(file));
  for (std::string line; std::getline(in, line);)
    if (!line.empty()) lines.push_back(nlohmann::json::parse(line));
  return lines;
}

// SPEC §6: a recording made on a site replays in the office: `record`, then `replay`,
// gives the same telegrams in the same order, at their times divided by the speed.
TEST_F(Transport, ARecordingReplaysTheSameTelegramsInOrderAndTime) {
  const auto first = dir.path() / "site" / "unimabus.jsonl";
  config.banks = "{ D1: 0x0011, D2: 0x0111, W: 0x0100 }";
  config.devices = "{ D1: { type: unigen-chp, address: 5 }, D2: { type: usc, address: 5 } }";
  config.unimabus_extra = "  record: { file: " + first.string() + " }\n";
  start();
  auto feed = feed_client();
  const std::vector<std::string> telegrams = {
      R"({"addr":5,"slot":0,"device":"unigen-chp","offset":1,"values":[1500,2,3]})",
      R"({"addr":5,"slot":0,"device":"usc","offset":3,"values":[-5]})",
      R"({"addr":5,"slot":2,"offset":0,"values":[11,12]})",
      R"({"addr":5,"slot":0,"device":"unigen-chp","offset":1,"values":[1501]})",
  };
  for (std::size_t i = 0; i < telegrams.size(); ++i) {
    if (i > 0) std::this_thread::sleep_for(std::chrono::milliseconds(300));  // the gaps the replay must keep
    feed.send(telegrams[i] + "\n");
  }
  ASSERT_TRUE(eventually([&] { return recorded_lines(first).size() == telegrams.size(); })) << read_file(first);
  daemon->terminate();
  const auto original = recorded_lines(first);
  for (std::size_t i = 0; i < telegrams.size(); ++i) {
    auto sent = nlohmann::json::parse(telegrams[i]);
    auto got = original[i];
    got.erase("t");
    if (sent["values"][0] == -5) sent["values"][0] = 65531;  // stored as two's complement
    EXPECT_EQ(got, sent) << i;
  }

  // Played at twice the speed by a second daemon, which records what it receives.
  const auto second = dir.path() / "office" / "unimabus.jsonl";
  config.transport = "replay";
  config.unimabus_extra = "  file: " + first.string() + "\n  speed: 2\n  offline_after: 2s\n" +
                          "  record: { file: " + second.string() + " }\n";
  config.modbus_port = free_port();
  start();
  ASSERT_TRUE(eventually([&] { return recorded_lines(second).size() == telegrams.size(); })) << daemon->log();
  const auto replayed = recorded_lines(second);
  // Each telegram is due at its "t" / 2 after the replay began, a moment apart from when
  // the second recorder began: the telegram played closest to its time says where the
  // replay began in the recorder's clock. Measured from another telegram, one played late
  // on a loaded machine would make the others look early; measured from there, a replay
  // at the wrong speed or one that does not wait spreads far beyond the tolerance.
  const auto lateness = [&](std::size_t i) {
    return replayed[i]["t"].get<double>() - original[i]["t"].get<double>() / 2;
  };
  double replay_began = lateness(0);
  for (std::size_t i = 1; i < telegrams.size(); ++i) replay_began = std::min(replay_began, lateness(i));
  for (std::size_t i = 0; i < telegrams.size(); ++i) {
    auto a = original[i], b = replayed[i];
    a.erase("t");
    b.erase("t");
    EXPECT_EQ(b, a) << i;
    EXPECT_LT(lateness(i) - replay_began, 0.25) << "telegram " << i << " played off its time";
  }
  ModbusClient client(config.modbus_port);
  EXPECT_EQ(client.read_input(0x0012, 3), (std::vector<std::uint16_t>{1501, 2, 3}));
  EXPECT_EQ(client.read_input(0x0114, 1), std::vector<std::uint16_t>{65531});
  // After the last line the devices fall silent and go off-line, like a bus that stopped.
  EXPECT_TRUE(daemon->wait_for_log("D1 (unigen-chp at UnimaBUS address 5) off-line", 5000ms)) << daemon->log();
  EXPECT_TRUE(eventually([&] { return client.read_input(0x1033, 1) == std::vector<std::uint16_t>{0}; }));
}

TEST_F(Transport, AReplayLoopsWhenToldTo) {
  const auto file = dir.path() / "loop.jsonl";
  test_support::write_file(file,
                           "{\"t\":0,\"addr\":5,\"slot\":0,\"offset\":1,\"values\":[100]}\n"
                           "\n"
                           "{\"t\":0.2,\"addr\":5,\"slot\":0,\"offset\":1,\"values\":[200]}\n");
  config.transport = "replay";
  config.unimabus_extra = "  file: " + file.string() + "\n  loop: true\n";
  start();
  ModbusClient client(config.modbus_port);
  // 100, 200, and 100 again: only a second pass writes 100 after 200.
  bool saw_200 = false, saw_100_after = false;
  ASSERT_TRUE(eventually([&] {
    const auto v = client.read_input(0x0012, 1);
    if (v && (*v)[0] == 200) saw_200 = true;
    if (v && (*v)[0] == 100 && saw_200) saw_100_after = true;
    return saw_100_after;
  })) << daemon->log();
}

TEST_F(Transport, ABadRecordingIsAnErrorNamingFileAndLine) {
  const auto file = dir.path() / "bad.jsonl";
  test_support::write_file(file,
                           "{\"t\":0.5,\"addr\":5,\"slot\":0,\"offset\":1,\"values\":[100]}\n"
                           "{\"t\":0.25,\"addr\":5,\"slot\":0,\"offset\":1,\"values\":[200]}\n");
  config.transport = "replay";
  config.unimabus_extra = "  file: " + file.string() + "\n";
  const auto config_file = dir.path() / "replay.yaml";
  test_support::write_file(config_file, config.yaml());
  auto checked = run(std::string(UNIMA_BRIDGE_CLI) + " check --config " + config_file.string());
  EXPECT_NE(checked.status, 0);
  EXPECT_NE(checked.output.find(file.string() + ":2: \"t\" goes back from 0.5 to 0.25"), std::string::npos)
      << checked.output;

  test_support::write_file(file, "{\"t\":0,\"addr\":5,\"slot\":0,\"offset\":1}\n");
  checked = run(std::string(UNIMA_BRIDGE_CLI) + " check --config " + config_file.string());
  EXPECT_NE(checked.output.find(file.string() + ":1: missing \"values\""), std::string::npos) << checked.output;

  // The daemon refuses to start on it, naming the same place.
  Daemon refused(dir, config.yaml());
  EXPECT_TRUE(eventually([&] { return !refused.running(); })) << refused.log();
  EXPECT_NE(refused.log().find(file.string() + ":1:"), std::string::npos) << refused.log();
}

TEST_F(Transport, TheRecordingIsRotatedInWholeLines) {
  const auto file = dir.path() / "rec" / "unimabus.jsonl";
  config.transport = "sim";
  config.unimabus_extra = "  sim: { period: 10ms }\n  record: { file: " + file.string() + ", max_size: 4096, max_files: 2 }\n";
  start();
  ASSERT_TRUE(eventually([&] { return std::filesystem::exists(file.string() + ".2"); }, 10000ms)) << daemon->log();
  daemon->terminate();
  for (const auto& path : {file, std::filesystem::path(file.string() + ".1"), std::filesystem::path(file.string() + ".2")}) {
    EXPECT_LE(std::filesystem::file_size(path), 4096u) << path;
    const auto text = read_file(path);
    ASSERT_FALSE(text.empty()) << path;
    EXPECT_EQ(text.back(), '\n') << path;
    EXPECT_NO_THROW((void)unimabus::parse_recording(text, path.string())) << path;  // every line whole
  }
  EXPECT_FALSE(std::filesystem::exists(file.string() + ".3"));
}

}  // namespace
}  // namespace unima::test
