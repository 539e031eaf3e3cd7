#include "state/state_journal.hpp"

#include <charconv>
#include <optional>
#include <vector>

#include <fmt/format.h>

#include "state/crc32.hpp"

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

// "W 3 1234 8c7f0b1e" or "W 3 1234 + 5d1c02e4" (without its newline) -> the record, or why not.
std::optional<Record> parse_record(std::string_view line, std::string& why) {
  const auto last_space = line.rfind(' ');
  std::uint32_t crc = 0;
  if (last_space == std::string_view::npos || line.size() - last_space - 1 != 8 ||
      !parse_number(line.substr(last_space + 1), crc, 16)) {
    why = "no checksum";
    return std::nullopt;
  }
  auto body = line.substr(0, last_space);
  if (crc32(body) != crc) {
    why = "checksum mismatch";
    return std::nullopt;
  }
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
  const auto body = record_body(value, continued);
  return fmt::format("{} {:08x}\n", body, crc32(body));
}

std::string encode_image(const StateImage& image) {
  std::string text(journal_header);
  for (const auto& value : image.values()) text += encode_record(value);
  return text;
}

LoadedJournal parse_journal(std::string_view bytes) {
  LoadedJournal loaded;
  if (bytes.empty()) return loaded;
  if (!bytes.starts_with(journal_header)) {
    // A crash while the header of a new file was written leaves a part of it: nothing was
    // ever recorded there.
    if (journal_header.starts_with(bytes)) {
      loaded.status = LoadedJournal::Status::torn_tail;
      loaded.problem = "line 1: a torn header";
      return loaded;
    }
    loaded.status = LoadedJournal::Status::foreign;
    loaded.problem = bytes.starts_with("unima-bridge state ") ? "line 1: another version of the state file"
                                                             : "line 1: not a unima-bridge state file";
    return loaded;
  }
  // A write's values are applied once its last record is read: a write cut short by a
  // crash adds nothing.
  std::vector<PersistedValue> write;
  std::size_t at = journal_header.size();
  loaded.good_bytes = at;
  std::size_t line_number = 1;
  while (at < bytes.size()) {
    ++line_number;
    const auto newline = bytes.find('\n', at);
    const bool last = newline == std::string_view::npos || newline + 1 == bytes.size();
    std::string why = "no end of line";
    std::optional<Record> record;
    if (newline != std::string_view::npos) record = parse_record(bytes.substr(at, newline - at), why);
    if (!record) {
      loaded.status = last ? LoadedJournal::Status::torn_tail : LoadedJournal::Status::damaged;
      loaded.problem = fmt::format("line {}: {}", line_number, why);
      break;
    }
    write.push_back(record->value);
    at = newline + 1;
    if (record->continued) continue;
    for (const auto& value : write) loaded.image.apply(value);
    loaded.records += write.size();
    loaded.good_bytes = at;
    write.clear();
  }
  if (loaded.status == LoadedJournal::Status::ok && !write.empty()) {
    loaded.status = LoadedJournal::Status::torn_tail;
    loaded.problem = fmt::format("line {}: the last record of its write is missing", line_number);
  }
  if (loaded.status == LoadedJournal::Status::damaged) {
    // SPEC §10: a damaged file gives nothing. The records before the damage may hold an
    // older value than the one last acknowledged, which a record after it replaced.
    loaded.image = {};
    loaded.records = 0;
    loaded.good_bytes = 0;
  }
  return loaded;
}

}  // namespace unima::state
