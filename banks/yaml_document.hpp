#pragma once
// Loading one YAML document of the project's data or config files: a syntax error
// (explained by banks/yaml_syntax where yaml-cpp's words do not say what is wrong), or a
// conversion yaml-cpp refuses while `read` walks the nodes, becomes an `Error` naming
// origin:line:column (yaml-cpp marks are 0-based, ours 1-based), like the errors `read`
// raises itself; a key written twice in a mapping is refused with both positions
// (banks/yaml_duplicate_keys). Shared by the device tables, the device profiles and the config loader;
// YamlFields is what the tables' and the profiles' readers ask of a node.

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <initializer_list>
#include <string>
#include <string_view>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "banks/number_text.hpp"
#include "banks/yaml_duplicate_keys.hpp"
#include "banks/yaml_syntax.hpp"

namespace unima::banks {

template <typename Error, typename Read>
auto read_yaml_document(std::string_view text, std::string_view origin, Read&& read) {
  const auto error = [&](const YAML::Exception& e) {
    return Error(fmt::format("{}:{}:{}: {}", origin, e.mark.line + 1, e.mark.column + 1, e.msg));
  };
  YAML::Node root;
  try {
    root = YAML::Load(std::string(text));
  } catch (const YAML::ParserException& e) {
    const auto explained = explain_yaml_syntax_error(text, e.mark.line, e.mark.column, e.msg);
    throw Error(fmt::format("{}:{}:{}: {}", origin, explained.line, explained.column, explained.message));
  }
  if (const auto twice = first_duplicate_key(root))
    throw Error(fmt::format("{}:{}:{}: '{}' is written twice in this mapping (first at line {}, column {}); only one "
                            "would count: merge the two",
                            origin, twice->second.line + 1, twice->second.column + 1, twice->key, twice->first.line + 1,
                            twice->first.column + 1));
  try {
    return read(root);
  } catch (const YAML::Exception& e) {
    throw error(e);
  }
}

/// Fields of a data file's nodes, each failure an `Error` naming origin:line:column.
template <typename Error>
class YamlFields {
 public:
  explicit YamlFields(std::string_view origin) : origin_(origin) {}

  std::string position(const YAML::Node& node) const {
    const auto mark = node.Mark();
    return fmt::format("{}:{}:{}", origin_, mark.line + 1, mark.column + 1);
  }
  [[noreturn]] void fail(const YAML::Node& node, std::string_view message) const {
    throw Error(fmt::format("{}: {}", position(node), message));
  }
  void only_keys(const YAML::Node& map, std::initializer_list<std::string_view> allowed) const {
    if (!map.IsMap()) fail(map, "expected a mapping");
    for (const auto& entry : map) {
      const auto& key = entry.first.Scalar();
      if (std::find(allowed.begin(), allowed.end(), key) == allowed.end())
        fail(entry.first, fmt::format("unknown key '{}' (known: {})", key, fmt::join(allowed, ", ")));
    }
  }
  /// The text of `map[key]`; "" when it is missing and not `required`.
  std::string text(const YAML::Node& map, const char* key, bool required) const {
    const auto node = map[key];
    if (!node) {
      if (required) fail(map, fmt::format("missing key '{}'", key));
      return {};
    }
    if (!node.IsScalar()) fail(node, fmt::format("'{}' must be a single value", key));
    return node.Scalar();
  }
  /// 0..max, decimal or 0x hex (banks/number_text).
  unsigned long number(const YAML::Node& node, unsigned long max) const {
    if (!node.IsScalar()) fail(node, "expected a number");
    const auto value = parse_number(node.Scalar());
    if (!value || *value > max) fail(node, fmt::format("'{}' is not a number from 0 to {}", node.Scalar(), max));
    return *value;
  }
  /// `true` or `false`, as YAML writes them.
  bool boolean(const YAML::Node& node) const {
    if (node.IsScalar() && (node.Scalar() == "true" || node.Scalar() == "false")) return node.Scalar() == "true";
    fail(node, "expected true or false");
  }

 private:
  std::string origin_;
};

}  // namespace unima::banks
