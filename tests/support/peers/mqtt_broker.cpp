#include "tests/support/peers/mqtt_broker.hpp"

#include <pwd.h>
#include <unistd.h>

#include <cctype>

#include "tests/support/loopback.hpp"
#include "tests/support/shell_command.hpp"
#include "tests/support/temp_files.hpp"

namespace unima::test_support {

Broker::Broker(const std::filesystem::path& dir, const std::string& listener_extra) : dir_(dir), port_(free_port()) {
  // Started as root, mosquitto would become the user `mosquitto`, who cannot write in the
  // test's directory: it stays who the test is.
  const auto* me = ::getpwuid(::geteuid());
  write_file(dir_ / "mosquitto.conf", "listener " + std::to_string(port_) + " 127.0.0.1\n" + listener_extra +
                                          "allow_anonymous true\npersistence false\n"
                                          "user " + std::string(me ? me->pw_name : "root") + "\n"
                                          "log_dest file " + (dir_ / "mosquitto.log").string() + "\n"
                                          // The default kinds, and subscriptions (subscriptions_to).
                                          "log_type error\nlog_type warning\nlog_type notice\nlog_type information\n"
                                          "log_type subscribe\n"
                                          "pid_file " + (dir_ / "mosquitto.pid").string() + "\n");
}

Broker::~Broker() { stop(); }

bool Broker::start() {
  const auto started = run("mosquitto -d -c " + (dir_ / "mosquitto.conf").string() + " 2>&1");
  return started.status == 0 && wait_for_port(port_);
}

void Broker::stop() {
  const auto pid_file = dir_ / "mosquitto.pid";
  if (!std::filesystem::exists(pid_file)) return;
  run("kill $(cat " + pid_file.string() + ") 2>/dev/null; while kill -0 $(cat " + pid_file.string() +
      ") 2>/dev/null; do sleep 0.02; done");
  std::filesystem::remove(pid_file);
}

void Broker::signal(int signo) const {
  run("kill -" + std::to_string(signo) + " $(cat " + (dir_ / "mosquitto.pid").string() + ")");
}

std::string Broker::subscribe(const std::string& topic, int count, int seconds) const {
  return run("mosquitto_sub -p " + std::to_string(port_) + " -t '" + topic + "' -v -C " + std::to_string(count) + " -W " +
             std::to_string(seconds) + " 2>&1")
      .output;
}

// mosquitto 2.0 logs a subscription as "CLIENT QOS TOPIC" with no newline after it: the
// next line's time may follow the topic at once.
std::size_t Broker::subscriptions_to(const std::string& topic) const {
  const auto log = read_file(dir_ / "mosquitto.log");
  const auto entry = " " + topic;
  std::size_t count = 0;
  for (auto at = log.find(entry); at != std::string::npos; at = log.find(entry, at + 1)) {
    const auto end = at + entry.size();
    if (end == log.size() || std::isdigit(static_cast<unsigned char>(log[end])) || log[end] == '\n') ++count;
  }
  return count;
}

void publish(const Broker& broker, const std::string& topic, const std::string& payload, bool retained) {
  run("mosquitto_pub -p " + std::to_string(broker.port()) + " -q 1 " + (retained ? "-r " : "") + "-t '" + topic + "' -m '" +
      payload + "'");
}

}  // namespace unima::test_support
