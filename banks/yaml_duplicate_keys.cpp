#include "banks/yaml_duplicate_keys.hpp"

#include <map>
#include <vector>

namespace unima::banks {

std::optional<DuplicateKey> first_duplicate_key(const YAML::Node& root, std::size_t most_nodes) {
  const auto earlier = [](const YAML::Mark& a, const YAML::Mark& b) {
    return a.line != b.line ? a.line < b.line : a.column < b.column;
  };
  std::optional<DuplicateKey> found;
  std::size_t visited = 0;
  // Depth first with an explicit stack: a deeply nested document cannot exhaust ours.
  std::vector<YAML::Node> stack{root};
  while (!stack.empty() && visited < most_nodes) {
    const auto node = stack.back();
    stack.pop_back();
    ++visited;
    if (node.IsMap()) {
      std::map<std::string, YAML::Mark> seen;
      std::vector<YAML::Node> values;
      for (const auto& entry : node) {
        if (entry.first.IsScalar()) {
          const auto [first, inserted] = seen.emplace(entry.first.Scalar(), entry.first.Mark());
          const auto second = entry.first.Mark();
          if (!inserted && (!found || earlier(second, found->second)))
            found = DuplicateKey{entry.first.Scalar(), first->second, second};
        }
        values.push_back(entry.second);
      }
      stack.insert(stack.end(), values.rbegin(), values.rend());
    } else if (node.IsSequence()) {
      std::vector<YAML::Node> items(node.begin(), node.end());
      stack.insert(stack.end(), items.rbegin(), items.rend());
    }
  }
  return found;
}

}  // namespace unima::banks
