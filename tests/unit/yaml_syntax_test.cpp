// A YAML file yaml-cpp refuses for its indentation is explained at the line that is wrong
// (banks/yaml_syntax): a tab, or a line indented unlike the lines it could belong to — in
// the config as in the device tables and profiles, which share the loader (issue 30, 6).

#include <gtest/gtest.h>

#include <string>

#include "banks/yaml_syntax.hpp"
#include "tests/support/config_parse_error.hpp"

namespace unima::banks {
namespace {

using test_support::config_parse_error;

TEST(YamlSyntax, ATabInALinesIndentationIsNamedAtTheTab) {
  EXPECT_EQ(config_parse_error("modbus:\n  tcp:\n    listen: 127.0.0.1\n\tport: 5020\n"),
            "bridge.yaml:4:1: a tab indents this line; YAML indents with spaces: replace the tab by spaces, as many "
            "as the lines it belongs with have");
  // After spaces, and where yaml-cpp said "illegal map value" at the line above.
  EXPECT_TRUE(config_parse_error("modbus:\n  tcp:\n  \tlisten: 127.0.0.1\n").starts_with("bridge.yaml:3:3: a tab indents"));
  EXPECT_TRUE(config_parse_error("modbus:\n\ttcp:\n\t\tport: 5020\n").starts_with("bridge.yaml:2:1: a tab indents"));
}

TEST(YamlSyntax, ALineBetweenItsSiblingsAndItsParentSaysWhichItSeemsToBelongTo) {
  EXPECT_EQ(config_parse_error("modbus:\n  tcp:\n    listen: 127.0.0.1\n   port: 5020\nhttp:\n  port: 8080\n"),
            "bridge.yaml:4:4: this line is indented by 3 spaces: the keys of 'tcp' above it by 4 ('listen' on line 3), "
            "those of 'modbus' by 2; it seems to belong to 'tcp': indent it by 4 spaces to be a key of 'tcp' like "
            "'listen' on line 3, or by 2 spaces to be a key of 'modbus'");
  EXPECT_TRUE(config_parse_error("modbus:\n  tcp:\n    listen: 127.0.0.1\n port: 5020\n")
                  .starts_with("bridge.yaml:4:2: this line is indented by 1 space: the keys of 'modbus' above it by "
                               "2 ('tcp' on line 2), those of the top level by 0; it seems to belong to 'modbus'"))
      << config_parse_error("modbus:\n  tcp:\n    listen: 127.0.0.1\n port: 5020\n");
}

TEST(YamlSyntax, ALineDeeperThanAKeyWithAValueIsNamed) {
  EXPECT_EQ(config_parse_error("modbus:\n  tcp:\n    listen: 127.0.0.1\n      port: 5020\n"),
            "bridge.yaml:4:7: this line is indented by 6 spaces, deeper than the line above ('listen' on line 3), "
            "which has its value on the same line and so cannot hold keys: indent it by 4 spaces to be a key of "
            "'tcp' like 'listen' on line 3");
}

TEST(YamlSyntax, ListItemsHaveTheirKeysAtTheItemsContent) {
  const auto error = config_parse_error("blocks:\n  - type: read\n    register: 5\n   source: D1+1\n");
  EXPECT_TRUE(error.starts_with("bridge.yaml:4:4: this line is indented by 3 spaces: the keys of an item of 'blocks' "
                                "above it by 4 ('type' on line 2)"))
      << error;
}

TEST(YamlSyntax, WellIndentedFlowAndBlockTextIsNotBlamedAndOtherErrorsStayYamlCpps) {
  // A mapping spread over lines, a block scalar: their lines are no indentation.
  const auto text = "a: { b: 1,\n c: 2 }\nd: |\n   text\n     more\ne: [1, 2\n";
  const auto explained = explain_yaml_syntax_error(text, 5, 8, "end of sequence flow not found");
  EXPECT_EQ(explained.line, 6);
  EXPECT_EQ(explained.column, 9);
  EXPECT_EQ(explained.message, "end of sequence flow not found");
  // Inside a { … } spread over lines a tab is only a blank, not indentation.
  EXPECT_EQ(explain_yaml_syntax_error("a: { b: 1,\n\tc: 2 }\nd: [1, 2\n", 2, 8, "end of sequence flow not found").message,
            "end of sequence flow not found");
}

// Issue 44, finding 2: a ':' left out ("address 5") gave yaml-cpp's "illegal map value"
// one line late, or an unknown key, or "must be a mapping".
TEST(YamlSyntax, AKeyWithoutItsColonIsNamedAtItsLineWithTheFix) {
  EXPECT_EQ(config_parse_error("modbus:\n  address 5\n  tcp: { port: 5020 }\n"),
            "bridge.yaml:2:3: this line has no ':' after its key, unlike 'tcp' on line 3: write 'address: 5'");
  EXPECT_EQ(config_parse_error("modbus:\n  tcp: { port: 5020 }\n  address 5\n"),
            "bridge.yaml:3:3: 'address 5' has no ':' after its key: write 'address: 5'");
  EXPECT_EQ(config_parse_error("modbus:\n  address 5\n"), "bridge.yaml:2:3: 'address 5' has no ':' after its key: write 'address: 5'");
  // After a nested mapping, among the keys it returned to.
  EXPECT_EQ(config_parse_error("modbus:\n  address: 5\n  tcp:\n    listen: 127.0.0.1\n  mode slave\n  rtu: x\n"),
            "bridge.yaml:5:3: this line has no ':' after its key, unlike 'rtu' on line 6: write 'mode: slave'");
}

}  // namespace
}  // namespace unima::banks
