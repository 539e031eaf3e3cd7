// A key written twice in one mapping is refused with both positions (issue 44, finding 1:
// a second `modbus:` pasted at the end of the installed bridge.yaml was silently dropped,
// and `check` said OK) — in the config as in the device tables and profiles, which share
// the loader (banks/yaml_document.hpp).

#include <gtest/gtest.h>

#include <string>

#include <fmt/format.h>

#include "banks/yaml_duplicate_keys.hpp"
#include "tests/support/config_parse_error.hpp"

namespace unima::banks {
namespace {

using test_support::config_parse_error;

TEST(YamlDuplicateKeys, ASectionWrittenTwiceIsRefusedNamingBothPositions) {
  const std::string installed =
      "modbus:\n"
      "  tcp: { listen: 127.0.0.1, port: 5020 }\n"
      "unimabus: { transport: sim }\n"
      "\n"
      "modbus:\n"
      "  rtu: { device: /dev/ttyS0 }\n";
  EXPECT_EQ(config_parse_error(installed),
            "bridge.yaml:5:1: 'modbus' is written twice in this mapping (first at line 1, column 1); only one would "
            "count: merge the two");
}

TEST(YamlDuplicateKeys, AKeyWrittenTwiceDeepInsideOrInAFlowMappingIsFoundToo) {
  EXPECT_EQ(config_parse_error("modbus:\n  tcp: { port: 502, listen: 0.0.0.0, port: 503 }\n"),
            "bridge.yaml:2:38: 'port' is written twice in this mapping (first at line 2, column 10); only one would "
            "count: merge the two");
  EXPECT_EQ(config_parse_error("banks: { D1: 0x1100 }\n"
                         "devices:\n"
                         "  D1: { type: unigen-chp, address: 5 }\n"
                         "  D1: { type: unigen-chp, address: 6 }\n"),
            "bridge.yaml:4:3: 'D1' is written twice in this mapping (first at line 3, column 3); only one would "
            "count: merge the two");
}

TEST(YamlDuplicateKeys, TheEarliestSecondWritingIsNamedAndEqualKeysInOtherMappingsAreFine) {
  const auto root = YAML::Load(
      "a: { x: 1, y: 2 }\n"
      "b: { x: 1, y: 2, y: 3 }\n"
      "list: [ { k: 1 }, { k: 2, k: 3 } ]\n"
      "c: 1\n"
      "c: 2\n");
  const auto found = first_duplicate_key(root);
  ASSERT_TRUE(found);
  EXPECT_EQ(found->key, "y");
  EXPECT_EQ(found->second.line, 1);
  EXPECT_EQ(found->first.line, 1);
  EXPECT_LT(found->first.column, found->second.column);
  EXPECT_FALSE(first_duplicate_key(YAML::Load("a: { x: 1 }\nb: { x: 1 }\nl: [ { x: 1 }, { x: 2 } ]\n")));
}

TEST(YamlDuplicateKeys, ADocumentOfAliasesIsCheckedOnlySoFar) {
  // Each level doubles the nodes an expanding walk would meet: 2^30 at the end.
  std::string text = "l0: &l0 [1, 1]\n";
  // One format, not a chain of "l" + std::string: GCC 12 at -O3 (the Release build of the
  // cross tree) takes that chain for a memcpy past any object (-Wstringop-overflow).
  for (int i = 1; i <= 30; ++i) text += fmt::format("l{0}: &l{0} [*l{1}, *l{1}]\n", i, i - 1);
  EXPECT_FALSE(first_duplicate_key(YAML::Load(text), 100'000));
}

}  // namespace
}  // namespace unima::banks
