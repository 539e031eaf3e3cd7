#include "web/connection_eviction.hpp"

#include <map>

namespace unima::web {

std::optional<std::size_t> connection_to_evict(std::span<const OpenConnection> open) {
  std::map<std::string_view, std::size_t> held;  // connections by host, busy ones too
  for (const auto& connection : open) ++held[connection.host];
  std::optional<std::size_t> chosen;
  const auto goes_before = [&](const OpenConnection& candidate, const OpenConnection& other) {
    const auto candidates_host = held[candidate.host];
    const auto others_host = held[other.host];
    if (candidates_host != others_host) return candidates_host > others_host;
    return candidate.last_activity < other.last_activity;
  };
  for (std::size_t i = 0; i < open.size(); ++i) {
    if (open[i].request_in_progress) continue;
    if (!chosen || goes_before(open[i], open[*chosen])) chosen = i;
  }
  return chosen;
}

}  // namespace unima::web
