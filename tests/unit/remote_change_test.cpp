// A config from afar (SPEC §19), its pure parts: what it may cost before it is parsed (an
// alias bomb, too many nodes, too many bytes), the answer every channel gives, and the one
// flow — one change at a time, applied only once its probe passed, else rolled back.

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "remote/change_answer.hpp"
#include "remote/change_flow.hpp"
#include "remote/yaml_budget.hpp"

namespace unima::remote {
namespace {

using namespace std::chrono_literals;

// The classic: nine levels of ten aliases each, a billion strings from a few hundred bytes.
std::string billion_laughs() {
  std::string text = "a: &a [\"lol\",\"lol\",\"lol\",\"lol\",\"lol\",\"lol\",\"lol\",\"lol\",\"lol\"]\n";
  for (char level = 'b'; level <= 'i'; ++level) {
    const char below = static_cast<char>(level - 1);
    text += std::string(1, level) + ": &" + level + " [";
    for (int i = 0; i < 9; ++i) text += std::string(i ? "," : "") + "*" + below;
    text += "]\n";
  }
  return text;
}

TEST(RemoteYamlBudget, AnAliasBombIsRefusedBeforeAnythingWalksIt) {
  const auto text = billion_laughs();
  ASSERT_LT(text.size(), 1024u);
  const auto why = over_budget(text);
  ASSERT_TRUE(why);
  EXPECT_NE(why->find("more than 10000 YAML nodes once its aliases are expanded"), std::string::npos) << *why;
}

TEST(RemoteYamlBudget, NodesAreCountedWithTheirAliasesExpandedUpToTheLimit) {
  // A mapping of 3 nodes anchored, and 4 aliases of it: 1 + (1 key + 3) + 4 × (1 key + 3).
  const std::string text = "base: &b { x: 1 }\nc1: *b\nc2: *b\nc3: *b\nc4: *b\n";
  EXPECT_FALSE(over_budget(text, {.max_bytes = 1024, .max_nodes = 21}));
  const auto why = over_budget(text, {.max_bytes = 1024, .max_nodes = 20});
  ASSERT_TRUE(why);
  EXPECT_NE(why->find("more than 20 YAML nodes once its aliases are expanded"), std::string::npos) << *why;
}

TEST(RemoteYamlBudget, AConfigOfOrdinarySizePassesAndSoDoesTextThatIsNotYaml) {
  std::string text = "modbus:\n  tcp: { listen: 127.0.0.1, port: 5020 }\nblocks:\n";
  for (int i = 0; i < 500; ++i) text += "  - { type: poll, device: 2, register: " + std::to_string(i) + ", output: 1 }\n";
  EXPECT_FALSE(over_budget(text)) << "a long, real config: 500 blocks of 7 nodes";
  EXPECT_FALSE(over_budget("modbus: [unclosed\n")) << "the config's parse says where the syntax breaks";
}

TEST(RemoteYamlBudget, TooManyBytesOrNodesIsRefusedWithTheLimit) {
  const std::string big(256 * 1024 + 1, '#');
  const auto bytes = over_budget(big);
  ASSERT_TRUE(bytes);
  EXPECT_EQ(*bytes, "the config is 262145 bytes, more than the 262144 a config from afar may have");
  EXPECT_FALSE(over_budget(std::string(256 * 1024, '#')));
  std::string many = "list:\n";
  for (int i = 0; i < 10'000; ++i) many += "  - 1\n";
  const auto nodes = over_budget(many);
  ASSERT_TRUE(nodes);
  EXPECT_EQ(*nodes, "the config has more than 10000 YAML nodes");
}

TEST(RemoteChangeAnswer, IsOneLineOfJsonWithEveryField) {
  ChangeAnswer a{change_id("modbus: {}\n"), Result::refused, {{3, 5, "unknown key 'prot'"}}, "the config has errors",
                 Source::mqtt, "fleet-7"};
  const auto text = answer_json(a);
  EXPECT_EQ(text.find('\n'), std::string::npos);
  const auto json = nlohmann::json::parse(text);
  EXPECT_EQ(json["id"], a.id);
  EXPECT_EQ(json["id"].get<std::string>().size(), 64u);
  EXPECT_EQ(json["result"], "refused");
  EXPECT_EQ(json["errors"], nlohmann::json::parse(R"([{"line":3,"column":5,"message":"unknown key 'prot'"}])"));
  EXPECT_EQ(json["reason"], "the config has errors");
  EXPECT_EQ(json["source"], "mqtt");
  EXPECT_EQ(json["by"], "fleet-7");
  a.by = "bad \xff byte";
  const auto replaced = nlohmann::json::parse(answer_json(a), nullptr, false);
  ASSERT_FALSE(replaced.is_discarded()) << "the sender's own bytes never stop an answer";
  EXPECT_EQ(replaced["by"], "bad \xEF\xBF\xBD byte");
}

TEST(RemoteChangeAnswer, ConfigErrorsGiveTheirLinesAndColumns) {
  const auto errors = errors_at("mqtt:config/set:4:3: unknown key 'prot' in modbus.tcp (known: listen, port)\n"
                                "mqtt:config/set:9:1: another\n"
                                "something without a position\n",
                                "mqtt:config/set");
  ASSERT_EQ(errors.size(), 3u);
  EXPECT_EQ(errors[0], (ErrorAt{4, 3, "unknown key 'prot' in modbus.tcp (known: listen, port)"}));
  EXPECT_EQ(errors[1], (ErrorAt{9, 1, "another"}));
  EXPECT_EQ(errors[2], (ErrorAt{0, 0, "something without a position"}));
  EXPECT_EQ(errors_at("other.yaml:2:2: x", "mqtt:config/set")[0].line, 0u) << "another file's position is not this text's";
}

const ChangeFlow::Clock::time_point t0{std::chrono::seconds(100)};

TEST(RemoteChangeFlow, OneChangeAtATimeTheSecondIsBusy) {
  ChangeFlow flow;
  EXPECT_FALSE(flow.begin({"aaa", Source::http, "alice"}));
  EXPECT_TRUE(flow.busy());
  flow.committed(t0, 30s);
  const auto busy = flow.begin({"bbb", Source::mqtt, "fleet"});
  ASSERT_TRUE(busy);
  EXPECT_EQ(busy->result, Result::busy);
  EXPECT_EQ(busy->id, "bbb");
  EXPECT_EQ(busy->by, "fleet");
  EXPECT_EQ(busy->reason, "another change (http by alice) is being probed");
  EXPECT_TRUE(flow.probing()) << "the change under way goes on";
}

TEST(RemoteChangeFlow, AppliedOnlyOnceEverythingTheConfigNamesWorks) {
  ChangeFlow flow;
  ASSERT_FALSE(flow.begin({"aaa", Source::mqtt, "fleet"}));
  flow.committed(t0, 30s);
  EXPECT_EQ(flow.deadline(), t0 + 30s);
  ProbeFacts facts{{{"modbus.tcp 0.0.0.0:502", true}, {"http 0.0.0.0:8443", false}}, false, std::nullopt};
  EXPECT_FALSE(flow.probe(facts, t0 + 1s)) << "not yet, and not yet at its end";
  facts.listeners[1].second = true;
  EXPECT_FALSE(flow.probe(facts, t0 + 2s)) << "the broker has not accepted the bridge yet";
  facts.broker = true;
  const auto applied = flow.probe(facts, t0 + 3s);
  ASSERT_TRUE(applied);
  EXPECT_EQ(applied->result, Result::applied);
  EXPECT_EQ(applied->id, "aaa");
  EXPECT_EQ(applied->source, Source::mqtt);
  EXPECT_FALSE(flow.busy());
}

TEST(RemoteChangeFlow, AProbeThatHasNotPassedByItsDeadlineRollsBackWithWhatWasMissing) {
  ChangeFlow flow;
  ASSERT_FALSE(flow.begin({"aaa", Source::cli, "root"}));
  flow.committed(t0, 30s);
  const ProbeFacts facts{{{"modbus.tcp 0.0.0.0:502", true}}, false, false};
  EXPECT_FALSE(flow.probe(facts, t0 + 30s - 1ms));
  const auto rolled_back = flow.probe(facts, t0 + 30s);
  ASSERT_TRUE(rolled_back);
  EXPECT_EQ(rolled_back->result, Result::rolled_back);
  EXPECT_EQ(rolled_back->reason, "the new config did not prove itself in time: the MQTT broker has not accepted the "
                                 "bridge; the HTTP server does not answer");
  EXPECT_FALSE(flow.busy());
  EXPECT_FALSE(flow.begin({"bbb", Source::cli, "root"})) << "free for the next change";
}

TEST(RemoteChangeFlow, ARefusalFreesTheFlowAndCarriesTheErrors) {
  ChangeFlow flow;
  ASSERT_FALSE(flow.begin({"aaa", Source::http, "alice"}));
  const auto refused = flow.refuse("the config has errors", {{2, 3, "bad"}});
  EXPECT_EQ(refused.result, Result::refused);
  EXPECT_EQ(refused.by, "alice");
  ASSERT_EQ(refused.errors.size(), 1u);
  EXPECT_FALSE(flow.busy());
  EXPECT_FALSE(flow.probe({}, t0)) << "nothing is probed";
}

}  // namespace
}  // namespace unima::remote
