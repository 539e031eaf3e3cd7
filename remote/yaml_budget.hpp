#pragma once
// What a config from afar may cost before anything builds it (SPEC §19). yaml-cpp's tree
// shares an anchored node among its aliases, but whoever walks the tree — the config's
// parse, a diff, an emitter — meets the node once per alias: a "billion laughs" text of a
// few hundred bytes is a walk of billions of nodes. So the nodes are counted from the
// parser's events, each alias as the whole node it names, and the count stops at the limit.

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

namespace unima::remote {

struct YamlBudget {
  std::size_t max_bytes = 256 * 1024;
  std::size_t max_nodes = 10'000;
};

/// Why `text` is over `budget` ("… nodes, more than 10000 …"); nullopt when it is within
/// it. A text that is not YAML is within budget: the config's own parse says what is wrong
/// with it, at its line and column.
std::optional<std::string> over_budget(std::string_view text, const YamlBudget& budget = {});

}  // namespace unima::remote
