#include "config/topic_filter.hpp"

#include <cstddef>

namespace unima::config {

namespace {

// The level of `text` that begins at `at` (up to the next `/` or the end).
std::string_view level_at(std::string_view text, std::size_t at) {
  const auto end = text.find('/', at);
  return text.substr(at, end == std::string_view::npos ? std::string_view::npos : end - at);
}

}  // namespace

std::optional<std::string> topic_filter_problem(std::string_view filter) {
  if (filter.empty()) return "it is empty";
  if (filter.find('\0') != std::string_view::npos) return "it holds a NUL";
  if (filter.front() == '$') return "it starts with $ (the broker's own topics)";
  for (std::size_t at = 0;;) {
    const auto level = level_at(filter, at);
    const bool wildcard = level.find_first_of("+#") != std::string_view::npos;
    if (wildcard && level != "+" && level != "#") return "+ and # must each be a whole level (a/+/b, a/#)";
    at += level.size();
    if (level == "#" && at != filter.size()) return "# must be the last level";
    if (at == filter.size()) return std::nullopt;
    ++at;  // the '/'
  }
}

bool topic_matches_filter(std::string_view filter, std::string_view topic) {
  if (!topic.empty() && topic.front() == '$' && !filter.empty() && (filter.front() == '+' || filter.front() == '#'))
    return false;
  std::size_t f = 0, t = 0;
  for (;;) {
    const auto wanted = level_at(filter, f);
    if (wanted == "#") return true;
    const auto level = level_at(topic, t);
    if (wanted != "+" && wanted != level) return false;
    f += wanted.size() + 1;
    t += level.size() + 1;
    if (f > filter.size()) return t > topic.size();
    // "a/#" matches "a": the topic ended where the filter's last level is `#`.
    if (t > topic.size()) return filter.substr(f) == "#";
  }
}

}  // namespace unima::config
