#include "banks/yaml_syntax.hpp"

#include <algorithm>
#include <optional>
#include <vector>

#include <fmt/format.h>

namespace unima::banks {

namespace {

std::vector<std::string_view> split_lines(std::string_view text) {
  std::vector<std::string_view> lines;
  while (!text.empty()) {
    const auto end = text.find('\n');
    auto line = text.substr(0, end);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    lines.push_back(line);
    if (end == std::string_view::npos) break;
    text.remove_prefix(end + 1);
  }
  return lines;
}

// A line YAML does not read for its structure: blank, or a comment.
bool structural(std::string_view line) {
  const auto first = line.find_first_not_of(" \t");
  return first != std::string_view::npos && line[first] != '#';
}

// The text before a comment, and without trailing blanks; quotes keep a '#'.
std::string_view without_comment(std::string_view content) {
  char quote = 0;
  for (std::size_t i = 0; i < content.size(); ++i) {
    const char c = content[i];
    if (quote) {
      if (c == quote) quote = 0;
    } else if (c == '"' || c == '\'') {
      quote = c;
    } else if (c == '#' && (i == 0 || content[i - 1] == ' ')) {
      content = content.substr(0, i);
      break;
    }
  }
  while (!content.empty() && content.back() == ' ') content.remove_suffix(1);
  return content;
}

// One structural line, as far as the indentation check needs it.
struct Entry {
  int number = 0;      // 1-based
  int indent = 0;      // spaces before the content
  bool item = false;   // "- ..."
  int item_indent = 0; // where an item's own content starts
  std::string key;     // "tcp" of "tcp:" or "- tcp: x"; empty for a plain value
  bool opens = false;  // "key:" with nothing after it: what follows, indented deeper, is its value
  bool scalar_block = false;  // "key: |" or "key: >": deeper lines are text
  int flow_depth = 0;  // unclosed { and [ at its end
};

Entry read_entry(std::string_view line, int number) {
  Entry e;
  e.number = number;
  e.indent = static_cast<int>(line.find_first_not_of(' '));
  auto content = without_comment(line.substr(static_cast<std::size_t>(e.indent)));
  e.item_indent = e.indent;
  if (content == "-" || content.starts_with("- ")) {
    e.item = true;
    const auto rest = content.find_first_not_of(' ', 1);
    e.item_indent = e.indent + static_cast<int>(rest == std::string_view::npos ? content.size() : rest);
    content = rest == std::string_view::npos ? std::string_view() : content.substr(rest);
  }
  char quote = 0;
  for (std::size_t i = 0; i < content.size(); ++i) {
    const char c = content[i];
    if (quote) {
      if (c == quote) quote = 0;
      continue;
    }
    if (c == '"' || c == '\'') quote = c;
    else if (c == '{' || c == '[') ++e.flow_depth;
    else if (c == '}' || c == ']') --e.flow_depth;
    else if (c == ':' && e.key.empty() && e.flow_depth == 0 && (i + 1 == content.size() || content[i + 1] == ' ')) {
      e.key = std::string(content.substr(0, i));
      auto value = content.substr(i + 1);
      while (!value.empty() && value.front() == ' ') value.remove_prefix(1);
      e.opens = value.empty();
      e.scalar_block = !value.empty() && (value.front() == '|' || value.front() == '>');
    }
  }
  return e;
}

// A level of the block structure: the lines at `indent` that are the keys (or items) of `owner`.
struct Level {
  int indent = 0;
  std::string owner;  // "'tcp'", "the top level", "an item of 'blocks'"
  int first_line = 0;
  std::string first_key;
};

std::string spaces(int n) { return fmt::format("{} space{}", n, n == 1 ? "" : "s"); }

std::string key_or_line(const Level& level) {
  return level.first_key.empty() ? fmt::format("line {}", level.first_line)
                                 : fmt::format("'{}' on line {}", level.first_key, level.first_line);
}

// Calls `visit` with each line that makes the block structure, up to `last_line`
// (1-based): neither blank nor a comment, nor the text of a block scalar ("key: |"), nor the
// inside of a { … } or [ … ] spread over lines. The first error `visit` returns ends it.
template <typename Visit>
std::optional<YamlSyntaxError> walk_block_entries(const std::vector<std::string_view>& lines, int last_line, Visit visit) {
  int flow_depth = 0;
  int text_above = -1;  // inside a block scalar: lines indented deeper than this are its text
  for (int i = 0; i < static_cast<int>(lines.size()) && i < last_line; ++i) {
    const auto line = lines[static_cast<std::size_t>(i)];
    if (!structural(line) || line.starts_with("---") || line.starts_with("...")) continue;
    const auto entry = read_entry(line, i + 1);
    if (text_above >= 0 && entry.indent > text_above) continue;
    text_above = -1;
    if (flow_depth > 0) {
      flow_depth = std::max(0, flow_depth + entry.flow_depth);
      continue;
    }
    if (auto error = visit(entry)) return error;
    flow_depth = std::max(0, entry.flow_depth);
    if (entry.scalar_block) text_above = entry.item_indent;
  }
  return std::nullopt;
}

// The first line, up to `last_line` (1-based), indented unlike any line it could belong to.
std::optional<YamlSyntaxError> misindented_line(const std::vector<std::string_view>& lines, int last_line) {
  std::vector<Level> levels;
  std::optional<Entry> previous;
  return walk_block_entries(lines, last_line, [&](const Entry& entry) -> std::optional<YamlSyntaxError> {
    const auto owner_of = [&](const Entry& e) {
      if (e.key.empty()) return levels.empty() ? std::string("the top level") : levels.back().owner;
      return fmt::format("'{}'", e.key);
    };
    if (levels.empty()) {
      levels.push_back({entry.indent, "the top level", entry.number, entry.key});
    } else if (previous && previous->opens && (entry.indent > previous->item_indent ||
                                               (entry.item && entry.indent == previous->item_indent))) {
      levels.push_back({entry.indent, owner_of(*previous), entry.number, entry.key});
    } else if (entry.indent > levels.back().indent) {
      const auto& above = *previous;
      const auto& level = levels.back();
      return YamlSyntaxError{
          entry.number, entry.indent + 1,
          fmt::format("this line is indented by {}, deeper than the line above ({}), which has its value on the same "
                      "line and so cannot hold keys: indent it by {} to be a key of {} like {}",
                      spaces(entry.indent), key_or_line({above.item_indent, "", above.number, above.key}),
                      spaces(level.indent), level.owner, key_or_line(level))};
    } else if (entry.indent < levels.back().indent) {
      auto inner = levels.back();
      while (!levels.empty() && levels.back().indent > entry.indent) {
        inner = levels.back();
        levels.pop_back();
      }
      if (levels.empty() || levels.back().indent != entry.indent) {
        const int outer_indent = levels.empty() ? 0 : levels.back().indent;
        const auto outer_owner = levels.empty() ? std::string("the top level") : levels.back().owner;
        const bool nearer_inner = inner.indent - entry.indent <= entry.indent - outer_indent;
        const auto inner_choice = fmt::format("by {} to be a key of {} like {}", spaces(inner.indent), inner.owner,
                                              key_or_line(inner));
        const auto outer_choice = fmt::format("by {} to be a key of {}", spaces(outer_indent), outer_owner);
        return YamlSyntaxError{
            entry.number, entry.indent + 1,
            fmt::format("this line is indented by {}: the keys of {} above it by {} ({}), those of {} by {}; it "
                        "seems to belong to {}: indent it {}, or {}",
                        spaces(entry.indent), inner.owner, inner.indent, key_or_line(inner), outer_owner, outer_indent,
                        nearer_inner ? inner.owner : outer_owner, nearer_inner ? inner_choice : outer_choice,
                        nearer_inner ? outer_choice : inner_choice)};
      }
    }
    if (entry.item && !entry.key.empty())  // "- key: …" starts a mapping at the item's content
      levels.push_back({entry.item_indent, fmt::format("an item of {}", levels.back().owner), entry.number, entry.key});
    previous = entry;
    previous->item_indent = entry.item && !entry.key.empty() ? entry.item_indent : entry.indent;
    return std::nullopt;
  });
}

std::optional<YamlSyntaxError> tab_indented_line(const std::vector<std::string_view>& lines, int last_line) {
  int flow_depth = 0;  // inside a { … } or [ … ] spread over lines a tab is only a blank
  for (int i = 0; i < static_cast<int>(lines.size()) && i < last_line; ++i) {
    const auto line = lines[static_cast<std::size_t>(i)];
    if (!structural(line)) continue;
    const auto indentation = line.substr(0, line.find_first_not_of(" \t"));
    const bool in_flow = flow_depth > 0;
    const auto rest = line.substr(indentation.size());
    flow_depth = std::max(0, flow_depth + read_entry(rest, i + 1).flow_depth);
    if (in_flow) continue;
    if (const auto tab = indentation.find('\t'); tab != std::string_view::npos)
      return YamlSyntaxError{i + 1, static_cast<int>(tab) + 1,
                             "a tab indents this line; YAML indents with spaces: replace the tab by spaces, as many as "
                             "the lines it belongs with have"};
  }
  return std::nullopt;
}

// A line among the keys of a mapping that has no ':' ("address 5" between "mode: slave"
// and "tcp: …"): yaml-cpp reads it as the start of a key and says "illegal map value" at
// the next line's ':' (issue 44).
std::optional<YamlSyntaxError> colonless_line(const std::vector<std::string_view>& lines, int last_line) {
  std::optional<Entry> colonless;  // the last line without a key, at its indentation
  return walk_block_entries(lines, last_line, [&](const Entry& entry) -> std::optional<YamlSyntaxError> {
    if (!entry.key.empty() && colonless && colonless->indent == entry.indent) {
      const auto content = without_comment(lines[static_cast<std::size_t>(colonless->number - 1)]
                                               .substr(static_cast<std::size_t>(colonless->indent)));
      const auto space = content.find(' ');
      const auto fix = space == std::string_view::npos
                           ? fmt::format("'{}:'", content)
                           : fmt::format("'{}: {}'", content.substr(0, space), content.substr(space + 1));
      return YamlSyntaxError{colonless->number, colonless->indent + 1,
                             fmt::format("this line has no ':' after its key, unlike '{}' on line {}: write {}",
                                         entry.key, entry.number, fix)};
    }
    colonless.reset();
    if (entry.key.empty() && !entry.item && entry.flow_depth == 0) colonless = entry;
    return std::nullopt;
  });
}

}  // namespace

YamlSyntaxError explain_yaml_syntax_error(std::string_view text, int line, int column, std::string_view parser_message) {
  const auto lines = split_lines(text);
  // yaml-cpp often notices a wrong line only at the next token, on the line before or after it.
  const int last_line = line + 2;
  if (auto tab = tab_indented_line(lines, last_line)) return *tab;
  if (auto misindented = misindented_line(lines, last_line)) return *misindented;
  if (auto colonless = colonless_line(lines, last_line)) return *colonless;
  return {line + 1, column + 1, std::string(parser_message)};
}

}  // namespace unima::banks
