#include "cli/register_map_format.hpp"

#include <algorithm>
#include <array>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "config/register_map_json.hpp"

namespace unima::cli {

namespace {

std::array<std::string, 10> columns(const config::MapRow& row) {
  return {fmt::format("0x{:04X}", row.address), row.bank,   fmt::format("0x{:02X}", row.offset), row.id,
          row.label,                            row.kind,   row.unit,
          fmt::format("{}", row.scale),         row.access, row.source};
}

constexpr std::array<const char*, 10> headers = {"address", "bank",  "offset", "id",     "label",
                                                 "kind",    "unit",  "scale",  "access", "source"};

// Display width in characters, not bytes: the labels are Czech UTF-8.
std::size_t width(const std::string& text) {
  return static_cast<std::size_t>(std::count_if(text.begin(), text.end(), [](char c) { return (c & 0xC0) != 0x80; }));
}

std::string csv_field(const std::string& text) {
  if (text.find_first_of(",\"\n") == std::string::npos) return text;
  std::string quoted = "\"";
  for (char c : text) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + "\"";
}

}  // namespace

std::string format_register_map(const std::vector<config::MapRow>& rows, MapFormat format) {
  std::string out;
  if (format == MapFormat::json) {
    auto array = nlohmann::json::array();
    for (const auto& row : rows) array.push_back(config::map_row_json(row));
    return array.dump(2) + "\n";
  }
  std::vector<std::array<std::string, 10>> cells;
  cells.reserve(rows.size());
  for (const auto& row : rows) cells.push_back(columns(row));
  if (format == MapFormat::csv) {
    for (std::size_t c = 0; c < headers.size(); ++c) out += fmt::format("{}{}", c ? "," : "", headers[c]);
    out += "\n";
    for (const auto& line : cells) {
      for (std::size_t c = 0; c < line.size(); ++c) out += fmt::format("{}{}", c ? "," : "", csv_field(line[c]));
      out += "\n";
    }
    return out;
  }
  std::array<std::size_t, 10> widths{};
  for (std::size_t c = 0; c < headers.size(); ++c) widths[c] = width(headers[c]);
  for (const auto& line : cells)
    for (std::size_t c = 0; c < line.size(); ++c) widths[c] = std::max(widths[c], width(line[c]));
  const auto emit = [&](const auto& line) {
    std::string text;
    for (std::size_t c = 0; c < line.size(); ++c) {
      const std::string value = line[c];
      text += value;
      if (c + 1 < line.size()) text += std::string(widths[c] - width(value) + 2, ' ');
    }
    while (!text.empty() && text.back() == ' ') text.pop_back();
    out += text + "\n";
  };
  emit(headers);
  for (const auto& line : cells) emit(line);
  return out;
}

}  // namespace unima::cli
