#pragma once
// Loading one YAML document of the project's data or config files: a syntax error, or a
// conversion yaml-cpp refuses while `read` walks the nodes, becomes an `Error` naming
// origin:line:column (yaml-cpp marks are 0-based, ours 1-based), like the errors `read`
// raises itself. Shared by the device tables, the device profiles and the config loader.

#include <yaml-cpp/yaml.h>

#include <string>
#include <string_view>

#include <fmt/format.h>

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
    throw error(e);
  }
  try {
    return read(root);
  } catch (const YAML::Exception& e) {
    throw error(e);
  }
}

}  // namespace unima::banks
