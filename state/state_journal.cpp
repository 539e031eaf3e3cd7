#include "state/state_journal.hpp"

#include <charconv>
#include <optional>

#include <fmt/format.h>

#include "state/crc32.hpp"

namespace unima::state {
namespace {

std::string record_body(const PersistedValue& value) {
  return fmt::format("{} {} {}", static_cast<char>(value.kind), value.index, value.value);
}

template <typename T>
bool parse_number(std::string_view text, T& out, int base = 10) {
  if (text.empty()) return false;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), out, base);
  return ec == std::errc() && end == text.data() + text.size();
}

// "W 3 1234 8c7f0b1e" (without its newline) -> the value, or why not.
std::optional<PersistedValue> parse_record(std::string_view line, std::string& why) {
  const auto last_space = line.rfind(' ');
  std::uint32_t crc = 0;
  if (last_space == std::string_view::npos || line.size() - last_space - 1 != 8 ||
      !parse_number(line.substr(last_space + 1), crc, 16)) {
    why = "no checksum";
    return std::nullopt;
  }
  const auto body = line.substr(0, last_space);
  if (crc32(body) != crc) {
    why = "checksum mismatch";
    return std::nullopt;
  }
  PersistedValue value;
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
  return value;
}

}  // namespace

std::string encode_record(const PersistedValue& value) {
  const auto body = record_body(value);
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
  std::size_t at = journal_header.size();
  std::size_t line_number = 1;
  while (at < bytes.size()) {
    ++line_number;
    const auto newline = bytes.find('\n', at);
    const bool last = newline == std::string_view::npos || newline + 1 == bytes.size();
    std::string why = "no end of line";
    std::optional<PersistedValue> value;
    if (newline != std::string_view::npos) value = parse_record(bytes.substr(at, newline - at), why);
    if (!value) {
      loaded.status = last ? LoadedJournal::Status::torn_tail : LoadedJournal::Status::damaged;
      loaded.problem = fmt::format("line {}: {}", line_number, why);
      break;
    }
    loaded.image.apply(*value);
    ++loaded.records;
    at = newline + 1;
  }
  loaded.good_bytes = at;
  return loaded;
}

}  // namespace unima::state
