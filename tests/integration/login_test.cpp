// Password guessing against `http.users` (issue 29, row 1) with the real daemon: one peer
// host (127.0.0.2 — all of 127/8 is the loopback's) keeps guessing, and neither the real
// user on another host nor a Modbus master notices; nor does a crowd of connections from
// one host close a login that waits for its check (issue 43, finding 7). The hashes are bcrypt, made by
// python3's crypt (glibc's crypt(3), as `htpasswd -B` would), at the cost each test needs.
// The requests are written by hand (tests/support/peers/http_exchange) so that a test
// picks each one's source address and sees its reply as it came.


#include <array>
#include <atomic>
#include <map>
#include <fstream>
#include <regex>
#include <thread>

#include "tests/integration/bridge_fixture.hpp"
#include "tests/support/base64.hpp"
#include "tests/support/peers/http_exchange.hpp"

namespace unima::test {
namespace {

using test_support::http_exchange;
using test_support::HttpReply;

constexpr auto guesser = "127.0.0.2";

using test_support::base64;

std::string get_request(const std::string& credentials) {
  return "GET /healthz HTTP/1.1\r\nHost: 127.0.0.1\r\nAuthorization: Basic " + base64(credentials) +
         "\r\nConnection: close\r\n\r\n";
}

std::string read_to_end(const Socket& socket) {
  std::string all;
  std::array<std::uint8_t, 4096> buffer{};
  for (long n; (n = read_before(socket.fd(), std::chrono::steady_clock::now() + 30s, buffer)) > 0;)
    all.append(reinterpret_cast<const char*>(buffer.data()), static_cast<std::size_t>(n));
  return all;
}

class Logins : public BridgeTest {
 protected:
  // Each test ends with the daemon stopped cleanly: with checks in flight or answered to
  // clients long gone, an AddressSanitizer build would exit otherwise.
  void TearDown() override {
    if (!daemon || !daemon->running()) return;
    EXPECT_TRUE(daemon->terminate(10s)) << daemon->log();
    EXPECT_EQ(daemon->exit_code(), 0) << daemon->log();
  }

  /// Adds `name` with a bcrypt hash of `password` at `cost` (2^cost rounds).
  void add_user(const std::string& name, const std::string& password, int cost) {
    const auto hashed = run("python3 -W ignore -c \"import crypt; print(crypt.crypt('" + password +
                            "', crypt.mksalt(crypt.METHOD_BLOWFISH, rounds=1 << " + std::to_string(cost) + ")))\"");
    ASSERT_EQ(hashed.status, 0) << hashed.output;
    ASSERT_TRUE(hashed.output.starts_with("$2b$")) << hashed.output;
    std::ofstream(dir.path() / "http-users", std::ios::app) << name << ":" << hashed.output;
  }

  /// `options`: more keys of `http`, e.g. ", max_clients: 4".
  void start_http(const std::string& options = "") {
    http_port = free_port();
    config.extra += "http: { listen: 127.0.0.1, port: " + std::to_string(http_port) +
                    ", users: " + (dir.path() / "http-users").string() + options + " }\n";
    start();
    ASSERT_TRUE(wait_for_port(http_port)) << daemon->log();
  }

  // A check may wait behind others' slow hashes, which a loaded machine makes slower still
  // (the worker runs at the lowest priority): as patient as read_to_end.
  HttpReply login(const std::string& credentials, const std::string& source = "127.0.0.1") const {
    return http_exchange(http_port, get_request(credentials), source, std::chrono::seconds(30));
  }

  /// A connection from `source` whose request for a check the daemon has read: it waits for
  /// the hash now.
  Socket waiting_login(const std::string& credentials, const std::string& source) const {
    auto socket = Socket::tcp_from(source, http_port);
    socket.send(get_request(credentials));
    EXPECT_TRUE(eventually([&] { return server_read_all(http_port, socket); }, 10s)) << source;
    return socket;
  }

  /// unima_bridge_http_password_checks_in_flight, scraped as `scraper` (a user whose header
  /// the daemon remembers once its first scrape is checked); -1 when unreadable.
  int checks_in_flight(const std::string& scraper) const {
    const auto metrics = http_exchange(http_port, "GET /metrics HTTP/1.1\r\nHost: 127.0.0.1\r\nAuthorization: Basic " +
                                                      base64(scraper) + "\r\nConnection: close\r\n\r\n");
    std::smatch found;
    static const std::regex line("\nunima_bridge_http_password_checks_in_flight (\\d+)\n");
    return metrics.status == 200 && std::regex_search(metrics.body, found, line) ? std::stoi(found[1]) : -1;
  }

  std::uint16_t http_port = 0;
};

// The filed daemon's limit was global (5 checks a second for everyone): a guesser fast
// enough to take its tokens — hashes cheap enough here that guesses outrun it — had the
// real user answered 429. Now the guesser's host is told to wait, nobody else.
TEST_F(Logins, AGuessingHostIsToldToWaitAndTheRealUserOnAnotherHostGetsIn) {
  add_user("technician", "right", 4);
  start_http();
  std::atomic<bool> guessing = true;
  std::atomic<int> told_to_wait = 0;
  std::atomic<int> refused = 0;
  std::string wait_reply;
  std::vector<std::thread> guessers;
  for (int g = 0; g < 4; ++g)
    guessers.emplace_back([&, g] {
      for (int i = 0; guessing; ++i) {
        const auto reply = login("technician:guess" + std::to_string(g) + "-" + std::to_string(i), guesser);
        if (reply.status == 429 && told_to_wait++ == 0) wait_reply = reply.head;
        if (reply.status == 401) ++refused;
      }
    });
  const bool limited = eventually([&] { return told_to_wait > 0; }, 10s);
  std::vector<int> real_user;
  for (int i = 0; i < 5; ++i) real_user.push_back(login("technician:right").status);
  guessing = false;
  for (auto& t : guessers) t.join();

  ASSERT_TRUE(limited) << daemon->log();
  EXPECT_EQ(real_user, std::vector<int>(5, 200)) << "the real user, from 127.0.0.1, while 127.0.0.2 guesses";
  EXPECT_GT(refused, 0) << "the guesses that were checked are refused";
  EXPECT_NE(wait_reply.find("Retry-After: 1"), std::string::npos) << wait_reply;
  EXPECT_TRUE(daemon->wait_for_log("http: 127.0.0.2:")) << daemon->log();
  EXPECT_EQ(daemon->log().find("http: 127.0.0.1:"), std::string::npos) << "the real user is not warned of\n" << daemon->log();
  ModbusClient client(config.modbus_port);
  EXPECT_TRUE(client.read_input(0x0011, 1));
}

// A slow hash (bcrypt, cost 14: about a second) is being checked while a Modbus master
// asks: the master's answer comes first. The filed daemon computed the hash on its event
// loop, so Modbus waited for it and the HTTP answer went out first.
TEST_F(Logins, AModbusRequestIsAnsweredWhileAPasswordIsChecked) {
  add_user("technician", "right", 14);
  start_http();
  ModbusClient client(config.modbus_port);
  ASSERT_TRUE(client.read_input(0x0011, 1));

  auto guess = Socket::tcp_from(guesser, http_port);
  ASSERT_TRUE(guess.valid());
  guess.send(get_request("technician:wrong"));
  // Once the daemon has read the request, its check has begun (the filed daemon's on the
  // loop, before it looks at any other socket again); only then does the master ask.
  ASSERT_TRUE(eventually([&] { return server_read_all(http_port, guess); }, 10s));
  const auto values = client.read_input(0x0011, 1);
  const bool http_answered_first = guess.readable_now();
  EXPECT_TRUE(values) << "Modbus: errno " << client.last_error();
  EXPECT_FALSE(http_answered_first) << "the HTTP answer came before Modbus'";
  EXPECT_EQ(test_support::parse_http_reply(read_to_end(guess)).status, 401);
}

// Many hosts at once: beyond 8 checks queued or running, 503 with Retry-After for the
// newcomers; the ones admitted are all answered.
TEST_F(Logins, ChecksBeyondTheQueueAreAskedToComeBack) {
  add_user("technician", "right", 12);
  start_http();
  std::vector<Socket> hosts;
  for (int h = 0; h < 12; ++h) {
    hosts.push_back(Socket::tcp_from("127.0.1." + std::to_string(h + 1), http_port));
    ASSERT_TRUE(hosts.back().valid());
    hosts.back().send(get_request("technician:wrong" + std::to_string(h)));
  }
  std::map<int, int> statuses;
  std::string busy_head;
  for (auto& host : hosts) {
    const auto reply = test_support::parse_http_reply(read_to_end(host));
    ++statuses[reply.status];
    if (reply.status == 503) busy_head = reply.head;
  }
  EXPECT_EQ(statuses[401], 8) << daemon->log();
  EXPECT_EQ(statuses[503], 4) << daemon->log();
  EXPECT_NE(busy_head.find("Retry-After: 1"), std::string::npos) << busy_head;
  EXPECT_TRUE(daemon->wait_for_log("password checks are waiting already")) << daemon->log();
}

// A browser's requests with the same new credentials at once cost one hash and all get in;
// a client that leaves while its check runs is forgotten; the daemon stops cleanly with a
// check under way.
TEST_F(Logins, TheSameCredentialsAtOnceShareOneCheckAndAClientThatLeavesIsForgotten) {
  add_user("technician", "right", 12);
  start_http();
  {
    auto leaving = Socket::tcp_from(guesser, http_port);
    leaving.send(get_request("technician:wrong"));
    ASSERT_TRUE(eventually([&] { return server_read_all(http_port, leaving); }, 10s));
  }  // closed while its check runs
  std::vector<Socket> tabs;
  for (int t = 0; t < 4; ++t) {
    tabs.push_back(Socket::tcp(http_port));
    tabs.back().send(get_request("technician:right"));
  }
  for (auto& tab : tabs) EXPECT_EQ(test_support::parse_http_reply(read_to_end(tab)).status, 200) << daemon->log();
  const auto metrics = http_exchange(http_port, "GET /metrics HTTP/1.1\r\nHost: 127.0.0.1\r\nAuthorization: Basic " +
                                                    base64("technician:right") + "\r\nConnection: close\r\n\r\n");
  ASSERT_EQ(metrics.status, 200);
  EXPECT_NE(metrics.body.find("\nunima_bridge_http_password_checks_total 2\n"), std::string::npos) << metrics.body;
  const auto file = dir.path() / "metrics.txt";
  test_support::write_file(file, metrics.body);
  const auto checked = run("promtool check metrics < " + file.string());
  EXPECT_EQ(checked.status, 0) << checked.output << metrics.body;

  auto last = Socket::tcp_from(guesser, http_port);
  last.send(get_request("technician:wrong again"));
  ASSERT_TRUE(eventually([&] { return server_read_all(http_port, last); }, 10s));
  // TearDown stops the daemon now, with that check under way.
}

// Issue 43, finding 7: one host's crowd of idle connections (its newest keep coming while a
// login waits for its hash, bcrypt cost 13) closed the real user's login, whose request had
// been read before any of theirs came, so it was "idle the longest". Now a connection with
// a request in progress never gives way, and the crowd's host, holding the most, does.
TEST_F(Logins, ACrowdOfConnectionsFromOneHostDoesNotCloseTheRealUsersLogins) {
  constexpr auto crowd_host = "127.0.0.3";
  for (int u = 0; u < 3; ++u) add_user("technician" + std::to_string(u), "right", 13);
  start_http(", max_clients: 4");
  std::vector<Socket> crowd;
  for (int c = 0; c < 3; ++c) crowd.push_back(Socket::tcp_from(crowd_host, http_port));
  for (int u = 0; u < 3; ++u) {
    auto real_user = waiting_login("technician" + std::to_string(u) + ":right", "127.0.0.1");
    // Eight more while the hash is computed: the filed daemon closed the login for the fourth.
    for (int c = 0; c < 8; ++c) crowd.push_back(Socket::tcp_from(crowd_host, http_port));
    EXPECT_EQ(test_support::parse_http_reply(read_to_end(real_user)).status, 200) << "login " << u << "\n" << daemon->log();
  }
  EXPECT_TRUE(daemon->wait_for_log("http: 4 connections is the limit: closing 127.0.0.3:")) << daemon->log();
  EXPECT_EQ(daemon->log().find("closing 127.0.0.1:"), std::string::npos) << daemon->log();
}

// Every connection has a request in progress (two logins waiting for their hashes, bcrypt
// cost 14): a newcomer is turned away rather than either closed. The filed daemon closed
// the login waiting the longest.
TEST_F(Logins, WhenEveryConnectionWaitsForItsAnswerANewcomerIsTurnedAway) {
  add_user("technician", "right", 14);
  start_http(", max_clients: 2");
  auto first = waiting_login("technician:wrong", guesser);
  auto second = waiting_login("technician:right", "127.0.0.1");
  auto newcomer = Socket::tcp_from("127.0.0.3", http_port);
  EXPECT_TRUE(newcomer.closed_by_peer(5s)) << daemon->log();  // within the request deadline (10 s)
  EXPECT_EQ(test_support::parse_http_reply(read_to_end(first)).status, 401) << daemon->log();
  EXPECT_EQ(test_support::parse_http_reply(read_to_end(second)).status, 200) << daemon->log();
  EXPECT_TRUE(daemon->wait_for_log("http: 2 connections is the limit and each has a request in progress: 127.0.0.3:"))
      << daemon->log();
  EXPECT_EQ(login("technician:right", "127.0.0.3").status, 200) << "with room again, the newcomer gets in";
}

// A client that leaves while its check waits gives its host's place back at once: the
// filed daemon kept the check, and its host was told to wait (429) until the hash was
// computed — a login closed by the eviction above locked its own user out that way.
TEST_F(Logins, AClientThatLeavesWhileItsCheckWaitsGivesItsHostsPlaceBack) {
  add_user("technician", "right", 14);
  add_user("prometheus", "scrape", 4);
  start_http();
  ASSERT_EQ(checks_in_flight("prometheus:scrape"), 0) << daemon->log();  // its header remembered from now on
  // Another host's check holds the worker for about a second; the leaver's queues behind it.
  auto other = waiting_login("technician:wrong", "127.0.0.4");
  {
    auto leaving = waiting_login("technician:wrong too", guesser);
  }  // closed
  ASSERT_TRUE(eventually([&] { return checks_in_flight("prometheus:scrape") <= 1; }, 10s)) << daemon->log();
  EXPECT_EQ(login("technician:wrong again", guesser).status, 401) << "a new check from the same host\n" << daemon->log();
  EXPECT_EQ(test_support::parse_http_reply(read_to_end(other)).status, 401);
  EXPECT_EQ(checks_in_flight("prometheus:scrape"), 0) << daemon->log();
}

}  // namespace
}  // namespace unima::test
