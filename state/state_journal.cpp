#include "state/state_journal.hpp"

#include <charconv>
#include <optional>
#include <vector>

#include <fmt/format.h>

#include "state/checked_lines.hpp"

namespace unima::state {
namespace {

constexpr std::string_view continuation_mark = " +";

std::string record_body(const PersistedValue& value, bool continued) {
  return fmt::format("{} {} {}{}", static_cast<char>(value.kind), value.index, value.value,
                     continued ? continuation_mark : std::string_view());
}

struct Record {
  PersistedValue value;
  bool continued = false;
};

template <typename T>
bool parse_number(std::string_view text, T& out, int base = 10) {
  if (text.empty()) return false;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), out, base);
  return ec == std::errc() && end == text.data() + text.size();
}

// "W 3 1234" or "W 3 1234 +" (a checked line's body) -> the record, or why not.
std::optional<Record> parse_record(std::string_view body, std::string& why) {
  Record record;
  record.continued = body.ends_with(continuation_mark);
  if (record.continued) body.remove_suffix(continuation_mark.size());
  auto& value = record.value;
  if (body.size() < 5 || body[1] != ' ') {
    why = "not a record";
    return std::nullopt;
  }
  const char kind = body[0];
  if (kind != 'W' && kind != 'X' && kind != 'O') {
    why = fmt::format("unknown kind '{}'", kind);
    return std::nullopt;
  }
  value.kind = static_cast<PersistedValue::Kind>(kind);
  const auto rest = body.substr(2);
  const auto space = rest.find(' ');
  if (space == std::string_view::npos || !parse_number(rest.substr(0, space), value.index) ||
      !parse_number(rest.substr(space + 1), value.value) || !valid_index(value.kind, value.index)) {
    why = "bad register or value";
    return std::nullopt;
  }
  return record;
}

}  // namespace

std::string encode_record(const PersistedValue& value, bool continued) {
  return checked_line(record_body(value, continued));
}

std::string encode_image(const StateImage& image) {
  std::string text(journal_header);
  for (const auto& value : image.values()) text += encode_record(value);
  return text;
}

LoadedJournal parse_journal(std::string_view bytes) {
  LoadedJournal loaded;
  // A write's values are applied once its last record is read: a write cut short by a
  // crash adds nothing.
  std::vector<PersistedValue> write;
  const auto walk = walk_journal(bytes, journal_header, "state file", "the last record of its write is missing",
                                 [&](std::string_view body, std::size_t, std::size_t) {
                                   LineVerdict verdict;
                                   const auto record = parse_record(body, verdict.why);
                                   if (!record) {
                                     verdict.kind = LineVerdict::Kind::bad;
                                     return verdict;
                                   }
                                   write.push_back(record->value);
                                   if (record->continued) {
                                     verdict.kind = LineVerdict::Kind::continued;
                                     return verdict;
                                   }
                                   for (const auto& value : write) loaded.image.apply(value);
                                   loaded.records += write.size();
                                   write.clear();
                                   return verdict;
                                 });
  loaded.status = walk.status;
  loaded.good_bytes = walk.good_bytes;
  loaded.problem = walk.problem;
  if (walk.status == JournalStatus::damaged || walk.status == JournalStatus::foreign) {
    // SPEC §10: a damaged file gives nothing. The records before the damage may hold an
    // older value than the one last acknowledged, which a record after it replaced.
    loaded.image = {};
    loaded.records = 0;
  }
  return loaded;
}

}  // namespace unima::state
