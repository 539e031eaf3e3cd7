#include "mqtt/history_journal.hpp"

#include <algorithm>
#include <charconv>
#include <numeric>

#include <fmt/format.h>

#include "banks/bank_id.hpp"
#include "state/checked_lines.hpp"

namespace unima::mqtt {
namespace {

bool parse_number(std::string_view text, std::uint64_t& out, int base = 10) {
  if (text.empty()) return false;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), out, base);
  return ec == std::errc() && end == text.data() + text.size();
}

// "E <sequence> <bank> <document>" (checked) -> the entry.
std::optional<HistoryEntry> entry_of(std::string_view body, std::string& why) {
  why = "not an entry";
  if (!body.starts_with("E ")) return std::nullopt;
  body.remove_prefix(2);
  const auto space = body.find(' ');
  const auto bank_end = space == std::string_view::npos ? space : body.find(' ', space + 1);
  HistoryEntry entry;
  if (bank_end == std::string_view::npos || !parse_number(body.substr(0, space), entry.sequence) || bank_end == space + 1 ||
      bank_end + 1 >= body.size())
    return std::nullopt;
  entry.bank = body.substr(space + 1, bank_end - space - 1);
  entry.document = body.substr(bank_end + 1);
  // The bank is a topic level when the entry is sent: one that is no bank of the bridge
  // ("D1/../x", "#") would be published under a topic the bridge never owns, or refused by
  // the broker and held forever (issue 43, finding 13).
  if (!banks::parse_bank_name(entry.bank)) {
    why = "not a bank of the bridge";
    return std::nullopt;
  }
  return entry;
}

}  // namespace

std::string encode_history_entry(const HistoryEntry& entry) {
  return state::checked_line(fmt::format("E {} {} {}", entry.sequence, entry.bank, entry.document));
}

std::string encode_history_acknowledged(std::uint64_t sequence) {
  return state::checked_line(fmt::format("A {}", sequence));
}

std::optional<HistoryEntry> parse_history_entry(std::string_view line) {
  std::string why;
  const auto body = state::checked_body(line, why);
  return body ? entry_of(*body, why) : std::nullopt;
}

LoadedHistory parse_history(std::string_view bytes) {
  using Verdict = state::LineVerdict;
  LoadedHistory loaded;
  const auto walk = state::walk_journal(
      bytes, history_header, "history buffer", "", [&](std::string_view body, std::size_t offset, std::size_t size) {
        Verdict verdict;
        if (body.starts_with("A ")) {
          std::uint64_t acknowledged = 0;
          if (!parse_number(body.substr(2), acknowledged)) return Verdict{Verdict::Kind::bad, "not an acknowledgement"};
          auto& pending = loaded.pending;
          pending.erase(pending.begin(), std::partition_point(pending.begin(), pending.end(), [&](const HistoryPlace& place) {
                          return place.sequence <= acknowledged;
                        }));
          return verdict;
        }
        const auto entry = entry_of(body, verdict.why);
        if (!entry) return Verdict{Verdict::Kind::bad, verdict.why};
        // Sequences only grow: one that does not is not this file's own.
        if (entry->sequence <= loaded.last_sequence)
          return Verdict{Verdict::Kind::bad, fmt::format("sequence {} after {}", entry->sequence, loaded.last_sequence)};
        loaded.pending.push_back({entry->sequence, offset, size});
        loaded.last_sequence = entry->sequence;
        return verdict;
      });
  loaded.status = walk.status;
  loaded.good_bytes = walk.good_bytes;
  loaded.problem = walk.problem;
  if (walk.status == state::JournalStatus::damaged) {
    loaded.pending.clear();
    loaded.last_sequence = 0;
  }
  return loaded;
}

std::size_t oldest_to_drop(std::span<const std::uint64_t> sizes, std::uint64_t room) {
  const auto total = std::accumulate(sizes.begin(), sizes.end(), std::uint64_t{0});
  if (total <= room) return 0;
  // How many of the oldest go for the rest to take `limit` bytes at most.
  const auto to_fit = [&](std::uint64_t limit) {
    auto left = total;
    std::size_t dropped = 0;
    while (dropped < sizes.size() && left > limit) left -= sizes[dropped++];
    return dropped;
  };
  // The eighth left free must not cost the newest entries that fit the room: a buffer so
  // small that one entry takes most of it keeps the newest, rewritten with each new entry.
  const auto with_an_eighth_free = to_fit(room - room / 8);
  return with_an_eighth_free < sizes.size() ? with_an_eighth_free : to_fit(room);
}

}  // namespace unima::mqtt
