#pragma once
// A key written twice in one mapping (issue 44: a second `modbus:` pasted at the end of the
// installed bridge.yaml). yaml-cpp keeps both and hands out the first, so the second is
// silently dropped; every data and config file is refused with both positions instead
// (banks/yaml_document.hpp asks this after loading).

#include <yaml-cpp/yaml.h>

#include <optional>
#include <string>

namespace unima::banks {

struct DuplicateKey {
  std::string key;
  YAML::Mark first;   // yaml-cpp's 0-based marks
  YAML::Mark second;  // the one that would be dropped
};

/// The first key written twice in any mapping of `root`, in document order of the second
/// writing. Only scalar keys are compared. A document whose aliases would expand past
/// `most_nodes` is checked as far as that (a config is far smaller).
std::optional<DuplicateKey> first_duplicate_key(const YAML::Node& root, std::size_t most_nodes = 1'000'000);

}  // namespace unima::banks
