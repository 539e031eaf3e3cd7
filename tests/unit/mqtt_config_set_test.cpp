// Configs from afar over MQTT (SPEC §19, issue 40): which configs take them on
// <prefix>/config/set, what a message there is (a config, a retained one to clear, the
// clearing itself) and who is named as its author (mqtt/config_set.hpp).

#include <gtest/gtest.h>

#include <string>

#include "config/config.hpp"
#include "mqtt/config_set.hpp"
#include "mqtt/response_topic.hpp"

namespace unima::mqtt {
namespace {

config::Config config_set_site(bool remote_mqtt, bool with_mqtt = true) {
  config::Config config;
  if (with_mqtt) {
    config.mqtt.emplace();
    config.mqtt->topic = "fleet/site-17";
    config.mqtt->response_topics = {"fleet/site-17/reply/#"};
  }
  config.remote_config.emplace();
  config.remote_config->mqtt = remote_mqtt;
  return config;
}

TEST(MqttConfigSet, OnlyRemoteConfigMqttWithAnMqttSectionTakesConfigs) {
  EXPECT_TRUE(takes_configs(config_set_site(true)));
  EXPECT_FALSE(takes_configs(config_set_site(false)));
  EXPECT_FALSE(takes_configs(config_set_site(true, false)));
  auto without_section = config_set_site(true);
  without_section.remote_config.reset();
  EXPECT_FALSE(takes_configs(without_section));
}

TEST(MqttConfigSet, TopicsAreUnderThePrefixAndNeitherIsACommandOrTheOther) {
  EXPECT_EQ(config_set_topic("fleet/site-17"), "fleet/site-17/config/set");
  EXPECT_EQ(config_result_topic("fleet/site-17"), "fleet/site-17/config/result");
  // The commands' filter is <prefix>/set/#: config/set is not under it.
  EXPECT_FALSE(config_set_topic("fleet/site-17").starts_with("fleet/site-17/set/"));
  // Neither may be a Response Topic: an answer there would be a config, or our own result.
  const auto site = config_set_site(true);
  EXPECT_EQ(judge_response_topic(config_set_topic("fleet/site-17"), *site.mqtt), ResponseTopicVerdict::bridge_topic);
  EXPECT_EQ(judge_response_topic(config_result_topic("fleet/site-17"), *site.mqtt), ResponseTopicVerdict::bridge_topic);
}

TEST(MqttConfigSet, ARetainedConfigIsNeverAppliedAndAnEmptyMessageIsAClearing) {
  EXPECT_EQ(judge_config_message("modbus: {}\n", false), ConfigMessage::config);
  EXPECT_EQ(judge_config_message("modbus: {}\n", true), ConfigMessage::retained);
  // The bridge's own clearing comes back to it as a plain, empty message.
  EXPECT_EQ(judge_config_message("", false), ConfigMessage::clearing);
  EXPECT_EQ(judge_config_message("", true), ConfigMessage::clearing);
}

TEST(MqttConfigSet, TheAuthorIsTheUserPropertyByElseMqtt) {
  EXPECT_EQ(config_author({}), "mqtt");
  EXPECT_EQ(config_author({{"team", "ops"}}), "mqtt");
  EXPECT_EQ(config_author({{"by", ""}}), "mqtt");
  EXPECT_EQ(config_author({{"team", "ops"}, {"by", "alice"}, {"by", "mallory"}}), "alice");
}

TEST(MqttConfigSet, AnAuthorCannotForgeALogLineNorGrowWithoutBound) {
  EXPECT_EQ(config_author({{"by", "alice\nremote config: applied"}}), "alice?remote config: applied");
  const auto long_author = config_author({{"by", std::string(200, 'a')}});
  EXPECT_EQ(long_author, std::string(max_author_bytes, 'a'));
  // "é" is two bytes: cut before it, never in its middle.
  const auto accented = std::string(max_author_bytes - 1, 'a') + "\xC3\xA9";
  EXPECT_EQ(config_author({{"by", accented}}), std::string(max_author_bytes - 1, 'a'));
}

}  // namespace
}  // namespace unima::mqtt
