#include "mqtt/history_journal.hpp"

#include <algorithm>
#include <charconv>
#include <numeric>

#include <fmt/format.h>

#include "state/crc32.hpp"

namespace unima::mqtt {
namespace {

bool parse_number(std::string_view text, std::uint64_t& out, int base = 10) {
  if (text.empty()) return false;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), out, base);
  return ec == std::errc() && end == text.data() + text.size();
}

std::string with_checksum(const std::string& body) { return fmt::format("{} {:08x}\n", body, state::crc32(body)); }

// The line's body when its checksum holds, else why not.
std::optional<std::string_view> checked_body(std::string_view line, std::string& why) {
  if (line.ends_with('\n')) line.remove_suffix(1);
  const auto last_space = line.rfind(' ');
  std::uint64_t crc = 0;
  if (last_space == std::string_view::npos || line.size() - last_space - 1 != 8 ||
      !parse_number(line.substr(last_space + 1), crc, 16)) {
    why = "no checksum";
    return std::nullopt;
  }
  const auto body = line.substr(0, last_space);
  if (state::crc32(body) != crc) {
    why = "checksum mismatch";
    return std::nullopt;
  }
  return body;
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
  return entry;
}

}  // namespace

std::string encode_history_entry(const HistoryEntry& entry) {
  return with_checksum(fmt::format("E {} {} {}", entry.sequence, entry.bank, entry.document));
}

std::string encode_history_acknowledged(std::uint64_t sequence) { return with_checksum(fmt::format("A {}", sequence)); }

std::optional<HistoryEntry> parse_history_entry(std::string_view line) {
  std::string why;
  const auto body = checked_body(line, why);
  return body ? entry_of(*body, why) : std::nullopt;
}

LoadedHistory parse_history(std::string_view bytes) {
  LoadedHistory loaded;
  if (bytes.empty()) return loaded;
  if (!bytes.starts_with(history_header)) {
    // A crash while a new file's header was written leaves a part of it: nothing was in it.
    loaded.status = history_header.starts_with(bytes) ? LoadedHistory::Status::torn_tail : LoadedHistory::Status::foreign;
    loaded.problem = loaded.status == LoadedHistory::Status::torn_tail ? "line 1: a torn header"
                     : bytes.starts_with("unima-bridge mqtt history ") ? "line 1: another version of the history buffer"
                                                                         : "line 1: not a unima-bridge history buffer";
    return loaded;
  }
  std::uint64_t at = history_header.size();
  loaded.good_bytes = at;
  std::size_t line_number = 1;
  while (at < bytes.size()) {
    ++line_number;
    const auto newline = bytes.find('\n', at);
    const bool last = newline == std::string_view::npos || newline + 1 == bytes.size();
    std::string why = "no end of line";
    std::optional<std::string_view> body;
    if (newline != std::string_view::npos) body = checked_body(bytes.substr(at, newline - at), why);
    bool good = false;
    if (body && body->starts_with("A ")) {
      std::uint64_t acknowledged = 0;
      good = parse_number(body->substr(2), acknowledged);
      why = "not an acknowledgement";
      if (good) {
        auto& pending = loaded.pending;
        pending.erase(pending.begin(), std::partition_point(pending.begin(), pending.end(), [&](const HistoryPlace& place) {
                        return place.sequence <= acknowledged;
                      }));
      }
    } else if (body) {
      if (const auto entry = entry_of(*body, why)) {
        // Sequences only grow: one that does not is not this file's own.
        good = entry->sequence > loaded.last_sequence;
        if (!good) why = fmt::format("sequence {} after {}", entry->sequence, loaded.last_sequence);
        else {
          loaded.pending.push_back({entry->sequence, at, newline + 1 - at});
          loaded.last_sequence = entry->sequence;
        }
      }
    }
    if (!good) {
      loaded.status = last ? LoadedHistory::Status::torn_tail : LoadedHistory::Status::damaged;
      loaded.problem = fmt::format("line {}: {}", line_number, why);
      break;
    }
    at = newline + 1;
    loaded.good_bytes = at;
  }
  if (loaded.status == LoadedHistory::Status::damaged) {
    loaded.pending.clear();
    loaded.last_sequence = 0;
    loaded.good_bytes = 0;
  }
  return loaded;
}

std::size_t oldest_to_drop(std::span<const std::uint64_t> sizes, std::uint64_t room) {
  auto total = std::accumulate(sizes.begin(), sizes.end(), std::uint64_t{0});
  if (total <= room) return 0;
  const auto target = room - room / 8;
  std::size_t dropped = 0;
  while (dropped < sizes.size() && total > target) total -= sizes[dropped++];
  return dropped;
}

}  // namespace unima::mqtt
