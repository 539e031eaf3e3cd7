#include "platform/journal_stream.hpp"

#include <charconv>
#include <cstdint>

namespace unima::platform {

namespace {

bool parse_decimal(std::string_view text, std::uint64_t& value) {
  if (text.empty()) return false;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  return ec == std::errc{} && end == text.data() + text.size();
}

}  // namespace

bool is_journal_stream(std::string_view journal_stream, dev_t device, ino_t inode) {
  const auto colon = journal_stream.find(':');
  if (colon == std::string_view::npos) return false;
  std::uint64_t stream_device = 0;
  std::uint64_t stream_inode = 0;
  if (!parse_decimal(journal_stream.substr(0, colon), stream_device)) return false;
  if (!parse_decimal(journal_stream.substr(colon + 1), stream_inode)) return false;
  return stream_device == static_cast<std::uint64_t>(device) && stream_inode == static_cast<std::uint64_t>(inode);
}

std::string_view journal_priority_prefix(spdlog::level::level_enum level) {
  switch (level) {
    case spdlog::level::trace:
    case spdlog::level::debug: return "<7>";
    case spdlog::level::info: return "<6>";
    case spdlog::level::warn: return "<4>";
    case spdlog::level::err: return "<3>";
    case spdlog::level::critical: return "<2>";
    default: return "";
  }
}

}  // namespace unima::platform
