// Where the bridge may answer an MQTT 5 command (SPEC §15, issue 43 finding 2): the
// Response Topics an attacker allowed to publish `<prefix>/set/#` used to get the bridge
// to publish on, each refused, and the topics mqtt.response_topics lists answered
// (mqtt/response_topic.hpp); the topic filters that list is made of (config/topic_filter).

#include <gtest/gtest.h>

#include <optional>
#include <string>

#include "config/topic_filter.hpp"
#include "mqtt/response_topic.hpp"

namespace unima::mqtt {
namespace {

using enum ResponseTopicVerdict;

/// The bridge of site 17: prefix fleet/site-17, the default list, Home Assistant's
/// discovery under homeassistant.
config::MqttConfig site_17() {
  config::MqttConfig mqtt;
  mqtt.topic = "fleet/site-17";
  mqtt.response_topics = {"fleet/site-17/reply/#"};
  mqtt.discovery = config::MqttDiscoveryConfig{.prefix = "homeassistant"};
  return mqtt;
}

TEST(ResponseTopic, UnderReplyIsAnsweredThere) {
  const auto mqtt = site_17();
  EXPECT_EQ(judge_response_topic("fleet/site-17/reply/abc", mqtt), answer_there);
  EXPECT_EQ(judge_response_topic("fleet/site-17/reply/app-3/42", mqtt), answer_there);
  EXPECT_EQ(judge_response_topic("fleet/site-17/reply/" + std::string(max_response_topic_bytes - 20, 'r'), mqtt),
            answer_there);
}

TEST(ResponseTopic, TheBridgesOwnTopicsAreRefused) {
  const auto mqtt = site_17();
  for (const auto* own : {"fleet/site-17/status", "fleet/site-17/birth", "fleet/site-17/A", "fleet/site-17/D1",
                          "fleet/site-17/W", "fleet/site-17/set/W/3", "fleet/site-17/set/result", "fleet/site-17",
                          "fleet/site-17/reply"})
    EXPECT_EQ(judge_response_topic(own, mqtt), bridge_topic) << own;
}

// Even where a list would let them through: what the bridge publishes for its own ends,
// Sparkplug's namespace, Home Assistant's and the broker's own are never an answer's.
TEST(ResponseTopic, OwnSparkplugDiscoveryAndBrokerTopicsAreRefusedWhateverTheList) {
  auto mqtt = site_17();
  mqtt.response_topics = {"#", "$SYS/#"};
  for (const auto* never :
       {"fleet/site-17/status", "fleet/site-17/set/W/3", "spBv1.0/plant-7/NCMD/bridge-17", "spBv1.0/plant-7/DCMD/bridge-17/D1",
        "spBv1.0/plant-7/NDEATH/bridge-17", "spBv1.0/STATE/scada-1", "spBv1.0", "homeassistant/sensor/x/config",
        "homeassistant/status", "$SYS/x", "$share/g/t"})
    EXPECT_EQ(judge_response_topic(never, mqtt), bridge_topic) << never;
  // A sibling whose name only begins like the prefix is not under it.
  EXPECT_EQ(judge_response_topic("fleet/site-170/reply/x", mqtt), answer_there);
  EXPECT_EQ(judge_response_topic("homeassistantx/y", mqtt), answer_there);
  // Without discovery, its prefix is nobody's.
  mqtt.discovery.reset();
  EXPECT_EQ(judge_response_topic("homeassistant/sensor/x/config", mqtt), answer_there);
}

TEST(ResponseTopic, TopicsOutsideTheListAreRefused) {
  const auto mqtt = site_17();
  for (const auto* elsewhere : {"fleet/site-18/set/W/3", "fleet/site-18/reply/x", "fleet-app/replies/17", "reply/x"})
    EXPECT_EQ(judge_response_topic(elsewhere, mqtt), not_listed) << elsewhere;
  auto none = mqtt;
  none.response_topics.clear();
  EXPECT_EQ(judge_response_topic("fleet/site-17/reply/abc", none), not_listed);
  auto apps = mqtt;
  apps.response_topics = {"apps/+/replies"};
  EXPECT_EQ(judge_response_topic("apps/scada/replies", apps), answer_there);
  EXPECT_EQ(judge_response_topic("apps/scada/replies/x", apps), not_listed);
  EXPECT_EQ(judge_response_topic("fleet/site-17/reply/abc", apps), not_listed);
}

TEST(ResponseTopic, WhatIsNoTopicToPublishOnIsRefused) {
  const auto mqtt = site_17();
  EXPECT_EQ(judge_response_topic("", mqtt), not_a_topic);
  EXPECT_EQ(judge_response_topic("fleet/site-17/reply/+", mqtt), not_a_topic);
  EXPECT_EQ(judge_response_topic("fleet/site-17/reply/#", mqtt), not_a_topic);
  EXPECT_EQ(judge_response_topic("#", mqtt), not_a_topic);
  EXPECT_EQ(judge_response_topic(std::string("fleet/site-17/reply/a\0b", 23), mqtt), not_a_topic);
  EXPECT_EQ(judge_response_topic("fleet/site-17/reply/" + std::string(30'000, 'x'), mqtt), not_a_topic);
  EXPECT_EQ(judge_response_topic("fleet/site-17/reply/" + std::string(max_response_topic_bytes - 19, 'x'), mqtt),
            not_a_topic);
}

TEST(TopicFilter, WhatIsAFilter) {
  for (const auto* good : {"a", "a/b", "+", "#", "a/+/b", "a/#", "+/+/#", "a//b", "/a"})
    EXPECT_EQ(config::topic_filter_problem(good), std::nullopt) << good;
  for (const auto* bad : {"", "a/#/b", "#/a", "a#", "a/b+", "+a/b", "a/#b", "$SYS/#", "$x"})
    EXPECT_NE(config::topic_filter_problem(bad), std::nullopt) << bad;
  EXPECT_NE(config::topic_filter_problem(std::string("a\0b", 3)), std::nullopt);
}

TEST(TopicFilter, MatchesAsABrokerDoes) {
  using config::topic_matches_filter;
  EXPECT_TRUE(topic_matches_filter("a/b", "a/b"));
  EXPECT_FALSE(topic_matches_filter("a/b", "a/b/c"));
  EXPECT_FALSE(topic_matches_filter("a/b/c", "a/b"));
  EXPECT_FALSE(topic_matches_filter("a/b", "a/bc"));
  EXPECT_TRUE(topic_matches_filter("a/+/c", "a/b/c"));
  EXPECT_FALSE(topic_matches_filter("a/+/c", "a/b/x/c"));
  EXPECT_TRUE(topic_matches_filter("a/+", "a/"));  // an empty level is a level
  EXPECT_FALSE(topic_matches_filter("+", "a/b"));
  EXPECT_TRUE(topic_matches_filter("a/#", "a"));  // the parent too (MQTT §4.7.1.2)
  EXPECT_TRUE(topic_matches_filter("a/#", "a/b/c"));
  EXPECT_FALSE(topic_matches_filter("a/#", "ab"));
  EXPECT_TRUE(topic_matches_filter("#", "x/y"));
  EXPECT_TRUE(topic_matches_filter("+/+/#", "x/y"));
  EXPECT_FALSE(topic_matches_filter("+/+/+", "x/y"));
  // A filter beginning with a wildcard does not reach the broker's $ topics (MQTT §4.7.2).
  EXPECT_FALSE(topic_matches_filter("#", "$SYS/x"));
  EXPECT_FALSE(topic_matches_filter("+/x", "$SYS/x"));
  EXPECT_TRUE(topic_matches_filter("$SYS/#", "$SYS/x"));
}

}  // namespace
}  // namespace unima::mqtt
