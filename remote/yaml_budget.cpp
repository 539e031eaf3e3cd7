#include "remote/yaml_budget.hpp"

#include <yaml-cpp/eventhandler.h>
#include <yaml-cpp/exceptions.h>
#include <yaml-cpp/parser.h>

#include <algorithm>
#include <map>
#include <sstream>
#include <vector>

#include <fmt/format.h>

namespace unima::remote {

namespace {

struct OverBudget {};

// Counts nodes as a walk of the built tree would meet them, saturating at the limit.
class NodeCounter final : public YAML::EventHandler {
 public:
  explicit NodeCounter(std::size_t limit) : limit_(limit) {}
  std::size_t nodes() const { return nodes_; }
  bool expanded_an_alias() const { return expanded_; }

  void OnDocumentStart(const YAML::Mark&) override {}
  void OnDocumentEnd() override {}
  void OnNull(const YAML::Mark&, YAML::anchor_t anchor) override { leaf(anchor); }
  void OnScalar(const YAML::Mark&, const std::string&, YAML::anchor_t anchor, const std::string&) override {
    leaf(anchor);
  }
  void OnAlias(const YAML::Mark&, YAML::anchor_t anchor) override {
    const auto size = sizes_.find(anchor);
    // An alias of an anchor not closed yet (a node naming itself) cannot be walked to its end.
    if (size == sizes_.end()) {
      expanded_ = true;
      throw OverBudget{};
    }
    if (size->second > 1) expanded_ = true;
    add(size->second);
  }
  void OnSequenceStart(const YAML::Mark&, const std::string&, YAML::anchor_t anchor, YAML::EmitterStyle::value) override {
    open(anchor);
  }
  void OnSequenceEnd() override { close(); }
  void OnMapStart(const YAML::Mark&, const std::string&, YAML::anchor_t anchor, YAML::EmitterStyle::value) override {
    open(anchor);
  }
  void OnMapEnd() override { close(); }

 private:
  void add(std::size_t n) {
    nodes_ = n > limit_ - std::min(nodes_, limit_) ? limit_ + 1 : nodes_ + n;
    if (nodes_ > limit_) throw OverBudget{};
  }
  void leaf(YAML::anchor_t anchor) {
    add(1);
    if (anchor != YAML::NullAnchor) sizes_[anchor] = 1;
  }
  void open(YAML::anchor_t anchor) {
    open_.push_back({anchor, nodes_});
    add(1);
  }
  void close() {
    if (open_.empty()) return;
    const auto [anchor, before] = open_.back();
    open_.pop_back();
    if (anchor != YAML::NullAnchor) sizes_[anchor] = nodes_ - before;
  }

  std::size_t limit_;
  std::size_t nodes_ = 0;
  bool expanded_ = false;
  std::map<YAML::anchor_t, std::size_t> sizes_;                 // an anchored node's size, aliases expanded
  std::vector<std::pair<YAML::anchor_t, std::size_t>> open_;    // collections under way: anchor, count before
};

}  // namespace

std::optional<std::string> over_budget(std::string_view text, const YamlBudget& budget) {
  if (text.size() > budget.max_bytes)
    return fmt::format("the config is {} bytes, more than the {} a config from afar may have", text.size(),
                       budget.max_bytes);
  std::istringstream in{std::string(text)};
  NodeCounter counter(budget.max_nodes);
  try {
    YAML::Parser parser(in);
    while (parser.HandleNextDocument(counter)) {
    }
  } catch (const OverBudget&) {
    return fmt::format("the config has more than {} YAML nodes{}", budget.max_nodes,
                       counter.expanded_an_alias() ? " once its aliases are expanded (an alias bomb?)" : "");
  } catch (const YAML::Exception&) {
    return std::nullopt;  // not YAML: the parse names where
  }
  return std::nullopt;
}

}  // namespace unima::remote
