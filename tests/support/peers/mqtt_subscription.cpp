#include "tests/support/peers/mqtt_subscription.hpp"

#include <gtest/gtest.h>

#include <csignal>
#include <sstream>

#include "tests/support/eventually.hpp"
#include "tests/support/shell_command.hpp"
#include "tests/support/temp_files.hpp"

namespace unima::test_support {

Subscription::Subscription(const Broker& broker, const std::filesystem::path& file, const std::string& topic, bool hex)
    : file_(file) {
  const auto probe = "probe/" + file.filename().string();
  const auto started = run("mosquitto_sub -p " + std::to_string(broker.port()) + " -t '" + topic + "' -t '" + probe + "' " +
                           (hex ? "-F '%t %x'" : "-v") + " > " + file.string() + " 2>&1 & echo $!");
  pid_ = std::stoi(started.output);
  const bool subscribed = eventually([&] {
    publish(broker, probe, "ready");
    return lines().find(probe + (hex ? " 7265616479" : " ready")) != std::string::npos;
  });
  EXPECT_TRUE(subscribed) << "mosquitto_sub did not subscribe to " << topic << ": " << lines();
}

Subscription::~Subscription() { ::kill(pid_, SIGTERM); }

std::string Subscription::lines() const { return whole_lines(read_file(file_)); }

DurableSubscription::DurableSubscription(const Broker& broker, const std::filesystem::path& file,
                                         const std::string& client_id, const std::vector<std::string>& topics)
    : file_(file) {
  std::string filters;
  for (const auto& topic : topics) filters += " -t '" + topic + "'";
  const auto started = run("mosquitto_sub -c -i " + client_id + " -q 1 -p " + std::to_string(broker.port()) + filters +
                           " -v > " + file.string() + " 2>&1 & echo $!");
  pid_ = std::stoi(started.output);
  EXPECT_TRUE(eventually([&] { return broker.subscriptions_to(topics.front()) >= 1; }))
      << "mosquitto_sub did not subscribe to " << topics.front();
}

DurableSubscription::~DurableSubscription() { ::kill(pid_, SIGTERM); }

std::string DurableSubscription::lines() const { return whole_lines(read_file(file_)); }

// mosquitto_sub writes a message's line as it comes: a line without its end may still be
// being written, and is left for the next look.
std::string whole_lines(std::string text) {
  const auto last_end = text.find_last_of('\n');
  text.erase(last_end == std::string::npos ? 0 : last_end + 1);
  return text;
}

std::vector<std::string> payloads(const std::string& lines, const std::string& topic) {
  std::vector<std::string> found;
  std::istringstream in(lines);
  for (std::string line; std::getline(in, line);)
    if (line.starts_with(topic + " ")) found.push_back(line.substr(topic.size() + 1));
  return found;
}

}  // namespace unima::test_support
