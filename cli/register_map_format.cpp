#include "cli/register_map_format.hpp"

#include <algorithm>
#include <array>
#include <optional>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "config/register_map_json.hpp"
#include "modbus/plc_numbers.hpp"

namespace unima::cli {

namespace {

// The PLC-style numbers of one row; one digit form for the whole map.
struct PlcNumbers {
  std::optional<unsigned> input, holding;
};

PlcNumbers plc_numbers(const config::MapRow& row, ServedFunctions served, modbus::PlcDigits digits) {
  const bool readable = row.access.find('R') != std::string::npos;
  const bool writable = row.access.find('W') != std::string::npos;
  PlcNumbers numbers;
  if (readable) numbers.input = modbus::plc_number(modbus::PlcTable::input, row.address, digits);
  if (writable || (readable && served.function_3))
    numbers.holding = modbus::plc_number(modbus::PlcTable::holding, row.address, digits);
  return numbers;
}

std::string text_of(const std::optional<unsigned>& number) { return number ? fmt::format("{}", *number) : ""; }

// The first twelve as before issue 44, so that an import set up on them keeps working;
// the columns of pairs and bytes after them.
constexpr std::array<const char*, 17> csv_headers = {
    "address", "bank",           "offset",           "id",        "label", "kind", "unit",    "scale",     "access",
    "source",  "input_register", "holding_register", "data_type", "part",  "bits", "partner", "word_order"};

std::array<std::string, 17> csv_columns(const config::MapRow& row, const PlcNumbers& numbers) {
  return {fmt::format("0x{:04X}", row.address),
          row.bank,
          fmt::format("0x{:02X}", row.offset),
          row.id,
          row.label,
          row.kind,
          row.unit,
          fmt::format("{}", row.scale),
          row.access,
          row.source,
          text_of(numbers.input),
          text_of(numbers.holding),
          row.data_type,
          std::string(config::part_name(row.part)),
          config::bits_of(row),
          row.partner ? fmt::format("0x{:04X}", *row.partner) : "",
          std::string(config::word_order(row))};
}

// The table's columns; the last, the label (with the source it shows), is cut to fit.
constexpr std::array<const char*, 9> table_headers = {"address", "input", "holding", "bank", "rw",
                                                      "unit",    "scale", "id",      "label"};
constexpr std::size_t widest_id_column = 24;  // a longer id takes room from its label

std::array<std::string, 9> table_columns(const config::MapRow& row, const PlcNumbers& numbers) {
  return {fmt::format("0x{:04X}", row.address),
          text_of(numbers.input),
          text_of(numbers.holding),
          row.bank,
          row.access,
          row.unit,
          fmt::format("{}", row.scale),
          row.id,
          row.source.empty() ? row.label : row.label.empty() ? row.source : row.source + " " + row.label};
}

// Display width in characters, not bytes: the labels are Czech UTF-8.
std::size_t width(const std::string& text) {
  return static_cast<std::size_t>(std::count_if(text.begin(), text.end(), [](char c) { return (c & 0xC0) != 0x80; }));
}

// At most `room` characters, the last an ellipsis when some were cut.
std::string cut(const std::string& text, std::size_t room) {
  if (width(text) <= room) return text;
  if (room < 6) return {};  // an ellipsis and a letter or two tell nothing
  std::string kept;
  std::size_t characters = 0;
  for (char c : text) {
    const bool starts_character = (c & 0xC0) != 0x80;
    if (starts_character && ++characters == room) break;
    kept += c;
  }
  return kept + "…";
}

std::string csv_field(const std::string& text) {
  if (text.find_first_of(",\"\n") == std::string::npos) return text;
  std::string quoted = "\"";
  for (char c : text) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + "\"";
}

template <std::size_t N>
std::string table(const std::array<const char*, N>& headers, const std::vector<std::array<std::string, N>>& cells) {
  std::array<std::size_t, N> widths{};
  for (std::size_t c = 0; c < N; ++c) widths[c] = width(headers[c]);
  for (const auto& line : cells)
    for (std::size_t c = 0; c + 1 < N; ++c) widths[c] = std::max(widths[c], width(line[c]));
  widths[N - 2] = std::min(widths[N - 2], std::max(widest_id_column, width(headers[N - 2])));
  std::string out;
  const auto emit = [&](const auto& line) {
    std::string text;
    std::size_t used = 0;
    for (std::size_t c = 0; c + 1 < N; ++c) {
      const std::string value = line[c];
      text += value;
      used += width(value);
      const std::size_t column_end = std::max(used, [&] {
        std::size_t end = 0;
        for (std::size_t k = 0; k <= c; ++k) end += widths[k] + 2;
        return end - 2;
      }());
      text += std::string(column_end - used + 2, ' ');
      used = column_end + 2;
    }
    text += cut(line[N - 1], used < map_table_width ? map_table_width - used : 0);
    while (!text.empty() && text.back() == ' ') text.pop_back();
    out += text + "\n";
  };
  emit(headers);
  for (const auto& line : cells) emit(line);
  return out;
}

}  // namespace

std::string format_register_map(const std::vector<config::MapRow>& rows, MapOutput output, ServedFunctions served) {
  const auto format = output.format;
  std::uint16_t highest = 0;
  for (const auto& row : rows) highest = std::max(highest, row.address);
  const auto digits = modbus::plc_digits_for(highest);
  if (format == MapFormat::json) {
    auto array = nlohmann::json::array();
    for (const auto& row : rows) {
      auto item = config::map_row_json(row);
      const auto numbers = plc_numbers(row, served, digits);
      item["input_register"] = numbers.input ? nlohmann::json(*numbers.input) : nlohmann::json();
      item["holding_register"] = numbers.holding ? nlohmann::json(*numbers.holding) : nlohmann::json();
      array.push_back(std::move(item));
    }
    return array.dump(2) + "\n";
  }
  if (format == MapFormat::csv) {
    std::string out(output.byte_order_mark ? utf8_byte_order_mark : "");
    for (std::size_t c = 0; c < csv_headers.size(); ++c) out += fmt::format("{}{}", c ? "," : "", csv_headers[c]);
    out += "\n";
    for (const auto& row : rows) {
      const auto line = csv_columns(row, plc_numbers(row, served, digits));
      for (std::size_t c = 0; c < line.size(); ++c) out += fmt::format("{}{}", c ? "," : "", csv_field(line[c]));
      out += "\n";
    }
    return out;
  }
  std::vector<std::array<std::string, table_headers.size()>> cells;
  cells.reserve(rows.size());
  for (const auto& row : rows) cells.push_back(table_columns(row, plc_numbers(row, served, digits)));
  return table(table_headers, cells);
}

}  // namespace unima::cli
