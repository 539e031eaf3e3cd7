// MQTT northbound (SPEC §12) against a real broker: Debian's `mosquitto`, started by each
// test on a loopback port, and its `mosquitto_sub` as the fleet's subscriber. The retained
// status and its will, a bank's document after feed telegrams, a device going off line,
// and a broker that goes away and comes back while Modbus clients read.

#include <algorithm>
#include <csignal>
#include <future>
#include <thread>

#include <nlohmann/json.hpp>

#include "tests/integration/bridge_fixture.hpp"
#include "tests/integration/state_outage.hpp"
#include "tests/support/peers/mqtt_broker.hpp"
#include "tests/support/peers/mqtt_subscription.hpp"
#include "tests/support/shell_command.hpp"

namespace unima::test {
namespace {

using namespace std::chrono_literals;
using test_support::Broker;
using test_support::payloads;
using test_support::publish;
using test_support::Subscription;

/// `text` with every `from` replaced by `to`.
std::string replaced(std::string text, const std::string& from, const std::string& to) {
  for (auto at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size())) text.replace(at, from.size(), to);
  return text;
}

class Mqtt : public BridgeTest {
 protected:
  void SetUp() override {
    BridgeTest::SetUp();
    broker = std::make_unique<Broker>(dir.path());
    ASSERT_TRUE(broker->start());
    config.extra += site_17_mqtt(*broker);
  }
  /// openssl's CA and certificates (server, operator, viewer, another CA's) in certs/
  /// (tests/integration/tls/make_certificates.sh).
  void make_certificates() const {
    const auto made = run(std::string(UNIMA_SOURCE_DIR) + "/tests/integration/tls/make_certificates.sh " +
                          (dir.path() / "certs").string());
    ASSERT_EQ(made.status, 0) << made.output;
  }
  std::string pem(const std::string& name) const { return (dir.path() / "certs" / name).string(); }
  /// The next document of `bank` that `holds` (subscribed before `action`, which makes it come).
  std::optional<nlohmann::ordered_json> document_after(const std::string& bank, const std::function<void()>& action,
                                                       const std::function<bool(const nlohmann::ordered_json&)>& holds) {
    const auto topic = "fleet/site-17/" + bank;
    Subscription subscription(*broker, dir.path() / ("sub-" + std::to_string(++subscriptions_)), topic);
    action();
    std::optional<nlohmann::ordered_json> found;
    eventually([&] {
      for (const auto& payload : payloads(subscription.lines(), topic)) {
        const auto document = nlohmann::ordered_json::parse(payload);
        if (holds(document)) {
          found = document;
          return true;
        }
      }
      return false;
    }, 6000ms);
    return found;
  }
  int subscriptions_ = 0;
  std::unique_ptr<Broker> broker;
};

TEST_F(Mqtt, StatusIsRetainedOnlineAndOfflineAfterACleanStop) {
  start();
  EXPECT_TRUE(eventually([&] { return broker->subscribe("fleet/site-17/status", 1, 1) == "fleet/site-17/status online\n"; }))
      << daemon->log();
  const auto subscribed = broker->subscriptions_to("fleet/site-17/status");
  auto offline = std::async(std::launch::async, [&] { return broker->subscribe("fleet/site-17/status", 2); });
  // Subscribed before the bridge goes, or "offline" would be published to no one.
  ASSERT_TRUE(eventually([&] { return broker->subscriptions_to("fleet/site-17/status") > subscribed; }));
  daemon->signal(SIGTERM);
  EXPECT_EQ(offline.get(), "fleet/site-17/status online\nfleet/site-17/status offline\n");
  EXPECT_NE(daemon->log().find("mqtt: connected to 127.0.0.1:" + std::to_string(broker->port()) + " as site-17"), std::string::npos);
}

// SIGKILL: no goodbye; the broker publishes the will.
TEST_F(Mqtt, AKilledBridgeIsOfflineByItsWill) {
  start();
  ASSERT_TRUE(eventually([&] { return broker->subscribe("fleet/site-17/status", 1, 1) == "fleet/site-17/status online\n"; }));
  const auto subscribed = broker->subscriptions_to("fleet/site-17/status");
  auto offline = std::async(std::launch::async, [&] { return broker->subscribe("fleet/site-17/status", 2); });
  ASSERT_TRUE(eventually([&] { return broker->subscriptions_to("fleet/site-17/status") > subscribed; }));
  daemon->signal(SIGKILL);
  EXPECT_EQ(offline.get(), "fleet/site-17/status online\nfleet/site-17/status offline\n");
}

TEST_F(Mqtt, TheD1DocumentCarriesFedValuesInUnitsThenNullWhenTheDeviceGoesOffLine) {
  config.unimabus_extra = "  offline_after: 1s\n";
  start();
  auto feed = feed_client();
  const auto fed = document_after("D1", [&] {
    feed_and_wait(feed, R"({"addr":5,"slot":0,"offset":1,"values":[1234]})", 0x0012, 1234);
  }, [](const nlohmann::ordered_json& d) { return d["engine_speed"] == 1234; });
  ASSERT_TRUE(fed);
  EXPECT_EQ((*fed)["online"], true) << fed->dump();
  EXPECT_TRUE((*fed)["time"].get<std::string>().ends_with("Z")) << fed->dump();
  EXPECT_TRUE((*fed)["oil_temperature"].is_null()) << "never measured: " << fed->dump();
  auto it = fed->begin();
  EXPECT_EQ(it.key(), "time");
  EXPECT_EQ((++it).key(), "online");

  // A value in tenths: oil_temperature (D1+0x21, scale 0.1) fed as 853 reads 85.3.
  const auto tenths = document_after("D1", [&] {
    feed_and_wait(feed, R"({"addr":5,"slot":0,"offset":33,"values":[853]})", 0x0011 + 33, 853);
  }, [](const nlohmann::ordered_json& d) { return d["oil_temperature"].is_number(); });
  ASSERT_TRUE(tenths);
  EXPECT_DOUBLE_EQ((*tenths)["oil_temperature"].get<double>(), 85.3) << tenths->dump();

  // Nothing heard for offline_after: off line, every value null, bits too, at once (on change).
  const auto gone = document_after("D1", [] {}, [](const nlohmann::ordered_json& d) { return d["online"] == false; });
  ASSERT_TRUE(gone);
  EXPECT_TRUE((*gone)["engine_speed"].is_null()) << gone->dump();
  EXPECT_TRUE((*gone)["oil_temperature"].is_null()) << gone->dump();
  EXPECT_TRUE((*gone)["control_inputs.remote_start"].is_null()) << gone->dump();
}

// Banks A and B show what the config maps into them, keyed as the config writes it.
TEST_F(Mqtt, AAndBAreKeyedByTheirMappingSources) {
  config.devices = "{ D1: { type: unigen-chp, address: 5 } }\nmapping:\n  A: [ D1.oil_temperature ]\n  B: [ D1+0x11.7, X.2 ]";
  start();
  auto feed = feed_client();
  const auto a = document_after("A", [&] {
    feed_and_wait(feed, R"({"addr":5,"slot":0,"offset":33,"values":[853]})", 0x0011 + 33, 853);
  }, [](const nlohmann::ordered_json& d) { return d["D1.oil_temperature"].is_number(); });
  ASSERT_TRUE(a);
  EXPECT_DOUBLE_EQ((*a)["D1.oil_temperature"].get<double>(), 85.3) << a->dump();
  const auto b = document_after("B", [&] {
    feed_and_wait(feed, R"({"addr":5,"slot":0,"offset":17,"values":[128]})", 0x0011 + 17, 128);
  }, [](const nlohmann::ordered_json& d) { return d["D1+0x11.7"] == true; });
  ASSERT_TRUE(b);
  // SPEC §17: a mapped bit is a boolean, and a source never written (X) is not published.
  EXPECT_FALSE(b->contains("X.2")) << b->dump();
}

// SPEC §17, as a historian subscribed to the bank documents stores them: an unsigned
// analog above 32767 as it is, a 32-bit pair as one value, a byte pair as two values in
// their own units, a byte of 255 as null, no halves and no reserves.
TEST_F(Mqtt, DocumentsCarryValuesAsTheSeedMeansThem) {
  config.banks = "{ D1: 0x0011, D2: 0x0200, W: 0x0100 }";
  config.devices = "{ D1: { type: unigen-chp, address: 5 }, D2: { type: uis, address: 6 } }";
  start();
  auto feed = feed_client();
  const auto d1 = document_after("D1", [&] {
    // engine_speed 41234 min-1 (unsigned in the table), operating hours low 25674, high 26.
    feed_and_wait(feed, R"({"addr":5,"slot":0,"offset":1,"values":[41234,25674,26]})", 0x0011 + 3, 26);
  }, [](const nlohmann::ordered_json& d) { return d["operating_hours"].is_number(); });
  ASSERT_TRUE(d1);
  EXPECT_EQ((*d1)["engine_speed"], 41234) << d1->dump();
  EXPECT_EQ((*d1)["operating_hours"], 26 * 65536 + 25674) << d1->dump();
  EXPECT_FALSE(d1->contains("operating_hours_low")) << d1->dump();
  EXPECT_FALSE(d1->contains("operating_hours_high")) << d1->dump();
  for (const auto& [key, value] : d1->items()) EXPECT_FALSE(key.starts_with("reserve")) << key;

  // knock_rank_1 (UIS+0x08): cylinder 3 in the low byte, level 128 × 0.78125 % in the high.
  const auto knock = document_after("D2", [&] {
    feed_and_wait(feed, R"({"addr":6,"slot":0,"offset":8,"values":[32771,65283]})", 0x0200 + 9, 65283);
  }, [](const nlohmann::ordered_json& d) { return d["knock_rank_1.level"].is_number(); });
  ASSERT_TRUE(knock);
  EXPECT_EQ((*knock)["knock_rank_1.cylinder"], 3) << knock->dump();
  EXPECT_DOUBLE_EQ((*knock)["knock_rank_1.level"].get<double>(), 100.0) << knock->dump();
  // knock_rank_2 = 0xFF03: level 255 is "not measured", the cylinder is still told.
  EXPECT_TRUE((*knock)["knock_rank_2.level"].is_null()) << knock->dump();
  EXPECT_EQ((*knock)["knock_rank_2.cylinder"], 3) << knock->dump();
  EXPECT_FALSE(knock->contains("knock_rank_1")) << "a byte pair is two values, not one: " << knock->dump();
}

// The broker goes away: Modbus serves on, the log says so once; it comes back: status and
// every bank are published again, with the values of now (not a backlog).
TEST_F(Mqtt, ABrokerThatGoesAndComesBackGetsEverythingAgainWhileModbusServesOn) {
  start();
  ASSERT_TRUE(eventually([&] { return broker->subscribe("fleet/site-17/status", 1, 1) == "fleet/site-17/status online\n"; }));
  broker->stop();
  ModbusClient client(config.modbus_port);
  auto feed = feed_client();
  feed_and_wait(feed, R"({"addr":5,"slot":0,"offset":1,"values":[777]})", 0x0012, 777);
  for (int i = 0; i < 50; ++i) ASSERT_TRUE(client.read_input(0x0011, 16));
  ASSERT_TRUE(eventually([&] { return daemon->log().find("mqtt: the connection to") != std::string::npos; })) << daemon->log();

  ASSERT_TRUE(broker->start());  // persistence off: it knows nothing retained
  Subscription subscription(*broker, dir.path() / "again", "fleet/site-17/+");
  EXPECT_TRUE(eventually([&] { return !payloads(subscription.lines(), "fleet/site-17/S7").empty(); }, 10000ms));
  const auto again = subscription.lines();
  const auto status = payloads(again, "fleet/site-17/status");
  ASSERT_FALSE(status.empty()) << again << daemon->log();
  EXPECT_EQ(status.front(), "online");
  const auto d1 = payloads(again, "fleet/site-17/D1");
  ASSERT_FALSE(d1.empty()) << again;
  EXPECT_EQ(nlohmann::json::parse(d1.front())["engine_speed"], 777);
  EXPECT_FALSE(payloads(again, "fleet/site-17/C").empty()) << again;
  EXPECT_TRUE(client.read_input(0x0011, 16));
  // Once each: one drop, one connection again.
  const auto log = daemon->log();
  std::size_t drops = 0;
  for (auto at = log.find("mqtt: the connection to"); at != std::string::npos; at = log.find("mqtt: the connection to", at + 1)) ++drops;
  EXPECT_EQ(drops, 1u) << log;
}

// mqtts: the broker's certificate checked against the CA and the name, the bridge's own
// certificate presented to a broker that requires one; certificates made by openssl.
TEST_F(Mqtt, OverTlsWithTheBrokersCaAndAClientCertificate) {
  broker.reset();
  ASSERT_NO_FATAL_FAILURE(make_certificates());
  broker = std::make_unique<Broker>(dir.path(), "cafile " + pem("ca.pem") + "\ncertfile " + pem("server.pem") + "\nkeyfile " +
                                                    pem("server.key") + "\nrequire_certificate true\n");
  ASSERT_TRUE(broker->start());
  config.extra = "mqtt: { broker: 'mqtts://localhost:" + std::to_string(broker->port()) + "', client_id: site-17, topic: fleet/site-17, " +
                 "ca: " + pem("ca.pem") + ", certificate: " + pem("operator.pem") + ", key: " + pem("operator.key") + " }\n";
  start();
  const auto subscribe = "mosquitto_sub -p " + std::to_string(broker->port()) + " --cafile " + pem("ca.pem") + " --cert " +
                         pem("viewer.pem") + " --key " + pem("viewer.key") + " -h localhost -t fleet/site-17/status -C 1 -W 2 2>&1";
  EXPECT_TRUE(eventually([&] { return run(subscribe).output == "online\n"; }, 8000ms)) << run(subscribe).output << daemon->log();
}

// Over mqtts a burst of commands is read a slice at a time too (io/loop_turn.hpp). A broker
// that batches its writes (EMQX, HiveMQ) puts many packets in one TLS record: what a read cut
// short by its budget leaves of the last record waits in OpenSSL's buffer, where the socket
// does not show it, and a wait for the socket would never end. It is read at the loop's
// next turn: every command is carried out, the last one included.
TEST_F(Mqtt, OverTlsABurstBatchedInTlsRecordsIsCarriedOutToTheLast) {
  broker.reset();
  ASSERT_NO_FATAL_FAILURE(make_certificates());
  const auto port = free_port();
  constexpr int commands = 2000;
  const auto batching_log = dir.path() / "batching-broker.log";
  auto options = test_support::writing_to(batching_log);
  options.search_path = true;
  test_support::ChildProcess batching({"python3", std::string(UNIMA_SOURCE_DIR) + "/tests/integration/mqtt/batching_broker.py",
                                       std::to_string(port), pem("server.pem"), pem("server.key"), "fleet/site-17/set/W/3",
                                       std::to_string(commands)},
                                      options);
  // It takes one connection, the bridge's: no probe of its port.
  ASSERT_TRUE(eventually([&] { return read_file(batching_log).find("listening") != std::string::npos; })) << read_file(batching_log);
  config.extra = "mqtt: { broker: 'mqtts://localhost:" + std::to_string(port) + "', client_id: site-17, topic: fleet/site-17, " +
                 "commands: true, ca: " + pem("ca.pem") + " }\n";
  start();
  ModbusClient client(config.modbus_port);
  EXPECT_TRUE(eventually([&] { return client.read_holding(0x0103, 1) == std::vector<std::uint16_t>{commands}; }, 10000ms))
      << "W3 = " << client.read_holding(0x0103, 1).value_or(std::vector<std::uint16_t>{0}).front() << "\n"
      << daemon->log() << read_file(batching_log);
}

// A broker whose certificate is not of the configured CA is refused, and said so once.
TEST_F(Mqtt, ABrokerWithACertificateOfAnotherCaIsRefused) {
  broker.reset();
  ASSERT_NO_FATAL_FAILURE(make_certificates());
  broker = std::make_unique<Broker>(dir.path(), "certfile " + pem("server.pem") + "\nkeyfile " + pem("server.key") + "\n");
  ASSERT_TRUE(broker->start());
  config.extra = "mqtt: { broker: 'mqtts://localhost:" + std::to_string(broker->port()) + "', client_id: site-17, " +
                 "ca: " + pem("other-ca.pem") + " }\n";
  start();
  EXPECT_TRUE(daemon->wait_for_log("mqtt: no connection to localhost:" + std::to_string(broker->port()), 8000ms)) << daemon->log();
  ModbusClient client(config.modbus_port);
  EXPECT_TRUE(client.read_input(0x0011, 1));
  EXPECT_EQ(daemon->log_count("mqtt: no connection to"), 1u) << daemon->log();
}

// MQTT 5, and a broker that lets in only a name with its password (the password kept in a
// file of its own, not in the config); a wrong one is refused by the broker, said once.
TEST_F(Mqtt, Version5WithTheNameAndPasswordTheBrokerRequires) {
  broker.reset();
  const auto passwd = dir.path() / "broker-passwd";
  ASSERT_EQ(run("mosquitto_passwd -c -b " + passwd.string() + " site-17 'right horse'").status, 0);
  broker = std::make_unique<Broker>(dir.path(), "password_file " + passwd.string() + "\n");
  // No anonymous clients: every one needs a name of the password file.
  test_support::write_file(dir.path() / "mosquitto.conf",
                           replaced(read_file(dir.path() / "mosquitto.conf"), "allow_anonymous true", "allow_anonymous false"));
  ASSERT_TRUE(broker->start());
  test_support::write_file(dir.path() / "mqtt-password", "right horse\n");
  config.extra = "mqtt: { broker: 'mqtt://127.0.0.1:" + std::to_string(broker->port()) + "', client_id: site-17, " +
                 "topic: fleet/site-17, version: 5, username: site-17, password_file: " + (dir.path() / "mqtt-password").string() + " }\n";
  start();
  const auto subscribe = "mosquitto_sub -V mqttv5 -u site-17 -P 'right horse' -p " + std::to_string(broker->port()) +
                         " -t fleet/site-17/status -C 1 -W 2 2>&1";
  EXPECT_TRUE(eventually([&] { return run(subscribe).output == "online\n"; }, 8000ms)) << run(subscribe).output << daemon->log();

  daemon->terminate();
  daemon.reset();
  test_support::write_file(dir.path() / "mqtt-password", "wrong horse\n");
  start();
  EXPECT_TRUE(daemon->wait_for_log("mqtt: no connection to 127.0.0.1:" + std::to_string(broker->port()), 8000ms)) << daemon->log();
  EXPECT_NE(daemon->log().find("the broker refused the connection: Not authorized"), std::string::npos) << daemon->log();
}

// A reload to another topic: the old one says offline, the new one online and every bank.
TEST_F(Mqtt, AReloadToAnotherTopicMovesTheBridgeThere) {
  start();
  ASSERT_TRUE(eventually([&] { return broker->subscribe("fleet/site-17/status", 1, 1) == "fleet/site-17/status online\n"; }));
  auto yaml = read_file(daemon->config_path());
  daemon->rewrite_config(replaced(yaml, "topic: fleet/site-17", "topic: fleet/site-18"));
  daemon->signal(SIGHUP);
  EXPECT_TRUE(eventually([&] { return broker->subscribe("fleet/site-18/status", 1, 1) == "fleet/site-18/status online\n"; }, 8000ms))
      << daemon->log();
  EXPECT_EQ(broker->subscribe("fleet/site-17/status", 1, 1), "fleet/site-17/status offline\n");
  EXPECT_FALSE(broker->subscribe("fleet/site-18/D1", 1, 2).empty());

  // A reload that leaves mqtt as it was (the section moved down a line) keeps the connection.
  yaml = read_file(daemon->config_path());
  daemon->rewrite_config("\n" + replaced(yaml, "topic: fleet/site-17", "topic: fleet/site-18"));
  daemon->signal(SIGHUP);
  ASSERT_TRUE(eventually([&] { return daemon->log_count("SIGHUP: reloading") == 2; })) << daemon->log();
  // What is tested is that nothing happens: no event says a connection will not come, so
  // the test gives one the time it would take.
  std::this_thread::sleep_for(300ms);
  EXPECT_EQ(daemon->log_count("mqtt: connected to"), 2u) << daemon->log();
}

// A broker that stalls (SIGSTOP: the connection stays, nothing is acknowledged) while D1
// changes, then dies and comes back: the subscriber gets the present, not the queue of
// documents made meanwhile (the complaint of "stale values re-sent as fresh").
TEST_F(Mqtt, AfterABrokerStallOnlyThePresentIsPublishedNotABacklog) {
  start();
  ASSERT_TRUE(eventually([&] { return broker->subscribe("fleet/site-17/status", 1, 1) == "fleet/site-17/status online\n"; }));
  auto feed = feed_client();
  broker->signal(SIGSTOP);
  for (int speed = 1; speed <= 30; ++speed) {
    feed.send(R"({"addr":5,"slot":0,"offset":1,"values":[)" + std::to_string(speed) + "]}\n");
    std::this_thread::sleep_for(110ms);  // each one a document of its own (at most one per 100 ms)
  }
  broker->signal(SIGKILL);
  broker->stop();
  ASSERT_TRUE(broker->start());
  Subscription subscription(*broker, dir.path() / "after", "fleet/site-17/D1");
  ASSERT_TRUE(eventually([&] { return !payloads(subscription.lines(), "fleet/site-17/D1").empty(); }, 10000ms)) << daemon->log();
  // A backlog would come before anything newer: a sentinel value fed now marks its end.
  feed.send(R"({"addr":5,"slot":0,"offset":1,"values":[31]})" "\n");
  const auto speed = [](const std::string& document) { return nlohmann::json::parse(document)["engine_speed"]; };
  std::vector<std::string> documents;
  ASSERT_TRUE(eventually([&] {
    documents = payloads(subscription.lines(), "fleet/site-17/D1");
    return !documents.empty() && speed(documents.back()) == 31;
  }, 10000ms)) << subscription.lines();
  while (!documents.empty() && speed(documents.back()) == 31) documents.pop_back();  // the sentinel's and any after it
  EXPECT_LE(documents.size(), 2u) << subscription.lines();
  for (const auto& document : documents) EXPECT_EQ(speed(document), 30) << document;
}

// commands: true — a write to W or X by MQTT is a Modbus write: in the bank, kept in the
// state file before the result says ok, sent to UnimaBUS; a bad one changes nothing and
// says why.
TEST_F(Mqtt, CommandsWriteWAndXLikeModbusAndAnswerOnTheResultTopic) {
  config.extra = replaced(config.extra, "publish:", "commands: true, publish:");
  config.extra += "state: { file: " + (dir.path() / "state").string() + " }\n";
  start();
  ASSERT_TRUE(eventually([&] { return broker->subscribe("fleet/site-17/status", 1, 1) == "fleet/site-17/status online\n"; }));
  auto feed = feed_client();
  Subscription results(*broker, dir.path() / "results", "fleet/site-17/set/result");
  publish(*broker, "fleet/site-17/set/W/3", "1234");
  EXPECT_TRUE(feed.wait_for_line(R"({"bank":"W","offset":3,"value":1234})"));
  publish(*broker, "fleet/site-17/set/X/2", "1");
  EXPECT_TRUE(feed.wait_for_line(R"({"bank":"X","offset":0,"value":4})"));
  // A good command is answered once the state file has it, a bad one at once: the bad ones
  // go after the good ones' answers, so that the answers come in the order asserted below.
  ASSERT_TRUE(eventually([&] { return payloads(results.lines(), "fleet/site-17/set/result").size() == 2; })) << results.lines();
  publish(*broker, "fleet/site-17/set/W/16", "1");
  publish(*broker, "fleet/site-17/set/X/1", "on");
  ASSERT_TRUE(eventually([&] { return payloads(results.lines(), "fleet/site-17/set/result").size() == 4; })) << results.lines();
  const auto answers = payloads(results.lines(), "fleet/site-17/set/result");
  EXPECT_EQ(answers[0], R"({"topic":"fleet/site-17/set/W/3","ok":true,"error":null})");
  EXPECT_EQ(answers[1], R"({"topic":"fleet/site-17/set/X/2","ok":true,"error":null})");
  EXPECT_EQ(answers[2], R"({"topic":"fleet/site-17/set/W/16","ok":false,"error":"W has the offsets 0..15, not '16'"})");
  EXPECT_EQ(answers[3], R"({"topic":"fleet/site-17/set/X/1","ok":false,"error":"the payload must be 0 or 1, not 'on'"})");

  ModbusClient client(config.modbus_port);
  EXPECT_EQ(client.read_holding(0x0103, 1), std::vector<std::uint16_t>{1234});
  // Kept: after a SIGKILL the value is back (the result said ok only once it was on the disk).
  daemon->signal(SIGKILL);
  ASSERT_TRUE(eventually([&] { return !daemon->running(); }));
  daemon.reset();
  start();
  ModbusClient after(config.modbus_port);
  EXPECT_EQ(after.read_holding(0x0103, 1), std::vector<std::uint16_t>{1234});
}

// A retained command sits in the broker's store and would be carried out at every start
// and reconnection, over what a Modbus master wrote since (issue 43, finding 3): it is
// dropped, counted and warned about; the same command published live is carried out.
// With MQTT 5 the broker is asked not to send it at all (Retain Handling 2).
TEST_F(Mqtt, ARetainedCommandIsNeverCarriedOutFromTheBrokersStore) {
  const auto without_commands = config.extra;
  for (const bool mqtt5 : {false, true}) {
    SCOPED_TRACE(mqtt5 ? "MQTT 5" : "MQTT 3.1.1");
    config.extra = replaced(without_commands, "publish:", std::string("commands: true, ") + (mqtt5 ? "version: 5, " : "") + "publish:");
    publish(*broker, "fleet/site-17/set/W/3", "1234", true);
    start();
    ASSERT_TRUE(eventually([&] { return broker->subscribe("fleet/site-17/status", 1, 1) == "fleet/site-17/status online\n"; }));
    auto feed = feed_client();
    Subscription results(*broker, dir.path() / (mqtt5 ? "results5" : "results"), "fleet/site-17/set/result");
    publish(*broker, "fleet/site-17/set/W/4", "77");  // live: carried out, and after the retained one had its chance
    ASSERT_TRUE(eventually([&] { return payloads(results.lines(), "fleet/site-17/set/result").size() == 1; })) << results.lines();
    EXPECT_EQ(payloads(results.lines(), "fleet/site-17/set/result")[0], R"({"topic":"fleet/site-17/set/W/4","ok":true,"error":null})");
    ModbusClient client(config.modbus_port);
    EXPECT_EQ(client.read_holding(0x0103, 2), (std::vector<std::uint16_t>{0x7FFF, 77}));  // W3 never written
    const auto status = nlohmann::json::parse(
        test_support::run(std::string(UNIMA_BRIDGE_CLI) + " status --json --socket " + config.status_socket).output)["mqtt"];
    EXPECT_EQ(status["retained_commands_dropped"], mqtt5 ? 0 : 1) << status.dump();
    EXPECT_EQ(daemon->log().find("a retained command on fleet/site-17/set/W/3 dropped") != std::string::npos, !mqtt5) << daemon->log();
    daemon.reset();
  }
}

// A command the state file's disk refuses (issue 29, row 2) changes nothing — not the
// bank, not UnimaBUS — and its result says why; once the disk takes writes again, so does
// the command. The outage as tests/integration/state_outage.hpp makes it.
TEST_F(Mqtt, ACommandTheStateFileRefusesChangesNothingAndItsResultSaysWhy) {
  config.extra = replaced(config.extra, "publish:", "commands: true, publish:");
  const auto state_file = dir.path() / "state";
  config.extra += "state: { file: " + state_file.string() + " }\n";
  config.log_level = "warn";
  config.blocks = state_outage::write_blocks();
  start();
  const auto w = state_outage::fill(config.modbus_port, 0x0100);
  daemon->signal(SIGKILL);
  ASSERT_TRUE(eventually([&] { return !daemon->running(); }));
  daemon.reset();
  start();  // the file compacted
  ASSERT_TRUE(eventually([&] { return broker->subscribe("fleet/site-17/status", 1, 1) == "fleet/site-17/status online\n"; }));
  auto feed = feed_client();
  Subscription results(*broker, dir.path() / "results", "fleet/site-17/set/result");
  state_outage::refuse_writes(*daemon, state_file);
  publish(*broker, "fleet/site-17/set/W/3", "54321");
  ASSERT_TRUE(eventually([&] { return payloads(results.lines(), "fleet/site-17/set/result").size() == 1; })) << results.lines();
  EXPECT_EQ(payloads(results.lines(), "fleet/site-17/set/result")[0],
            R"({"topic":"fleet/site-17/set/W/3","ok":false,"error":"the state file refused the write: nothing changed"})");
  {
    ModbusClient client(config.modbus_port);
    EXPECT_EQ(client.read_holding(0x0103, 1), std::vector<std::uint16_t>{w[3]});
  }
  state_outage::take_writes(*daemon);
  publish(*broker, "fleet/site-17/set/W/3", "54322");
  ASSERT_TRUE(eventually([&] { return payloads(results.lines(), "fleet/site-17/set/result").size() == 2; })) << results.lines();
  EXPECT_EQ(payloads(results.lines(), "fleet/site-17/set/result")[1], R"({"topic":"fleet/site-17/set/W/3","ok":true,"error":null})");
  // UnimaBUS: the next line after the refusal is the command that was taken.
  EXPECT_EQ(feed.read_line(), R"({"bank":"W","offset":3,"value":54322})");
}

// A burst of commands (issue 43, finding 6): every one is carried out and answered, and
// the last value is the one Modbus reads; Modbus is served while the burst goes on;
// the log holds a line for the first command and not one for each.
TEST_F(Mqtt, ABurstOfCommandsAllLandsWhileModbusIsServedAndTheLogStaysShort) {
  constexpr int commands = 5000;
  broker.reset();
  // The broker queues what the bridge has not read yet (it stops reading while too many
  // commands wait): room for the whole burst, where mosquitto's default (1,000) would drop
  // QoS 1 messages past it — the broker's policy, not the bridge's.
  broker = std::make_unique<Broker>(dir.path(), "max_queued_messages 20000\n");
  ASSERT_TRUE(broker->start());
  config.extra = site_17_mqtt(*broker, true) + "state: { file: " + (dir.path() / "state").string() + " }\n";
  start();
  ASSERT_TRUE(eventually([&] { return broker->subscribe("fleet/site-17/status", 1, 1) == "fleet/site-17/status online\n"; }));
  Subscription results(*broker, dir.path() / "results", "fleet/site-17/set/result");
  const auto answered = [&] { return payloads(results.lines(), "fleet/site-17/set/result").size(); };
  auto burst = std::async(std::launch::async, [&] {
    return test_support::run("seq 1 " + std::to_string(commands) + " | mosquitto_pub -p " + std::to_string(broker->port()) +
                             " -q 1 -t fleet/site-17/set/W/3 -l 2>&1");
  });
  ModbusClient client(config.modbus_port);
  // Reads until every command is answered: those that went while some were answered and
  // some were not are reads during the burst.
  int reads_during_burst = 0;
  ASSERT_TRUE(eventually([&] {
    const auto before = answered();
    if (before == static_cast<std::size_t>(commands)) return true;
    const auto read = client.read_holding(0x0103, 1);
    EXPECT_TRUE(read.has_value()) << client.last_error();
    if (read && before > 0 && answered() < static_cast<std::size_t>(commands)) ++reads_during_burst;
    return false;
  }, 60000ms)) << answered() << " answers\n" << daemon->log();
  EXPECT_EQ(burst.get().status, 0);
  EXPECT_GT(reads_during_burst, 0);
  const auto answers = payloads(results.lines(), "fleet/site-17/set/result");
  EXPECT_EQ(std::count(answers.begin(), answers.end(), R"({"topic":"fleet/site-17/set/W/3","ok":true,"error":null})"),
            commands);
  EXPECT_EQ(client.read_holding(0x0103, 1), std::vector<std::uint16_t>{commands});
  EXPECT_EQ(daemon->log_count("mqtt: fleet/site-17/set/W/3 = "), 1u) << daemon->log();
}

// commands off (the default): nothing is subscribed, nothing changes.
TEST_F(Mqtt, WithoutCommandsASetTopicChangesNothing) {
  start();
  ASSERT_TRUE(eventually([&] { return broker->subscribe("fleet/site-17/status", 1, 1) == "fleet/site-17/status online\n"; }));
  Subscription results(*broker, dir.path() / "results", "fleet/site-17/set/result");
  publish(*broker, "fleet/site-17/set/W/3", "1234");
  // What is tested is that nothing happens (no write, no result): no event marks the end of
  // a wait for nothing, so the test gives the command the time one would take.
  std::this_thread::sleep_for(500ms);
  ModbusClient client(config.modbus_port);
  EXPECT_EQ(client.read_holding(0x0103, 1), std::vector<std::uint16_t>{0x7FFF});
  EXPECT_EQ(payloads(results.lines(), "fleet/site-17/set/result"), std::vector<std::string>{}) << results.lines();
}

}  // namespace
}  // namespace unima::test
