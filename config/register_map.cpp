// The register map (`unima-bridge map`), as rows and as JSON (register_map_json.hpp).

#include "config/register_map.hpp"
#include "config/register_map_json.hpp"

#include <algorithm>

#include <fmt/format.h>

namespace unima::config {

namespace {

using banks::BankId;
using banks::RegisterDef;
using banks::RegisterKind;

const RegisterDef* source_register(const banks::BankShapes& shapes, const banks::SourceRef& source) {
  const auto* table = shapes[index_of(source.bank)].table;
  return table && source.offset < table->length() ? &table->registers[source.offset] : nullptr;
}

std::string mapped_bits(const std::array<std::optional<banks::SourceRef>, banks::Mapping::entries>& sources) {
  std::string text;
  for (std::size_t n = 0; n < sources.size(); ++n)
    if (sources[n]) text += fmt::format("{}.{}={}", text.empty() ? "" : " ", n, sources[n]->text);
  return text;
}

// The fields every row has; what pairs and bytes add is set where they are known.
MapRow row_of(std::uint16_t address, std::string bank, std::uint16_t offset, std::string id, std::string label,
              std::string kind, std::string unit, double scale, std::string access, std::string source,
              std::string data_type = "uint16") {
  MapRow row;
  row.address = address;
  row.bank = std::move(bank);
  row.offset = offset;
  row.id = std::move(id);
  row.label = std::move(label);
  row.kind = std::move(kind);
  row.unit = std::move(unit);
  row.scale = scale;
  row.access = std::move(access);
  row.source = std::move(source);
  row.data_type = std::move(data_type);
  return row;
}

// A row that reads `reg`'s raw value (its own bank, a copy in A, a read block) says what
// the table says of it; a 32-bit half is worth what one unit of that half is worth.
void describe(MapRow& row, const RegisterDef& reg) {
  row.label = reg.label;
  row.kind = std::string(banks::kind_name(reg.kind));
  row.unit = reg.unit;
  row.scale = banks::register_scale(reg);
  row.data_type = reg.kind == RegisterKind::analog && reg.is_signed ? "int16" : "uint16";
  if (reg.kind == RegisterKind::u32_low) row.part = RowPart::low;
  if (reg.kind == RegisterKind::u32_high) row.part = RowPart::high;
}

bool has_bytes(const RegisterDef& reg) {
  return (reg.kind == RegisterKind::byte_pair || reg.kind == RegisterKind::ascii_pair) && !reg.fields.empty();
}

// `row`, or with bytes_apart one row per byte of the byte or ASCII pair `reg` it reads:
// each byte its own identifier, label, unit and scale. A byte row of a copy (A, a read
// block) is named after the copy.
void add(std::vector<MapRow>& rows, MapRow row, const RegisterDef* reg, const MapShape& shape) {
  if (!shape.reserves && row.kind == banks::kind_name(RegisterKind::reserve)) return;
  if (!shape.bytes_apart || !reg || !has_bytes(*reg)) {
    rows.push_back(std::move(row));
    return;
  }
  const bool own_bank = row.id == reg->id;
  for (const auto& field : reg->fields) {
    MapRow byte = row;
    byte.id = own_bank ? field.id : row.id + "_" + field.id;
    byte.label = field.label;
    byte.unit = field.unit;
    byte.scale = field.scale;
    byte.data_type = reg->kind == RegisterKind::ascii_pair ? "char" : "uint8";
    byte.part = field.last_bit <= 7 ? RowPart::byte_low : RowPart::byte_high;
    rows.push_back(std::move(byte));
  }
}

MapRow table_row(std::uint16_t address, BankId bank, const RegisterDef& reg, const std::string& access) {
  auto row = row_of(address, std::string(banks::bank_name(bank)), reg.offset, reg.id, {}, {}, {}, 1.0, access, {});
  describe(row, reg);
  return row;
}

// The row of the 32-bit pair whose low half is `low`, read as one uint32 from its address
// and the next.
MapRow joined_pair_row(std::uint16_t address, BankId bank, const RegisterDef& low) {
  MapRow row = table_row(address, bank, low, "R");
  row.id = low.pair;
  row.label = banks::pair_label(low.label);
  row.kind = "u32_pair";
  row.scale = low.scale;
  row.data_type = "uint32";
  row.part = RowPart::pair;
  row.partner = static_cast<std::uint16_t>(address + 1);
  return row;
}

// The rows of a D_N, S_N or C register at `offset` of its window; the number of
// registers they took (2 for a joined pair).
std::uint16_t add_table_register(std::vector<MapRow>& rows, const banks::DeviceTable& table, BankId bank,
                                 const banks::Window& window, std::uint16_t offset, const Config& config,
                                 const MapShape& shape) {
  const auto address = static_cast<std::uint16_t>(window.first + offset);
  const auto& reg = table.registers[offset];
  // The parser checked that a u32_low's u32_high follows it.
  const bool high_served = offset + 1 < window.count && offset + 1 < table.length();
  if (reg.kind == RegisterKind::u32_low && high_served && shape.pairs_joined) {
    rows.push_back(joined_pair_row(address, bank, reg));
    return 2;
  }
  auto row = table_row(address, bank, reg, "R");
  if (reg.kind == RegisterKind::u32_low && high_served) row.partner = static_cast<std::uint16_t>(address + 1);
  if (reg.kind == RegisterKind::u32_high && offset > 0) row.partner = static_cast<std::uint16_t>(address - 1);
  if (bank == BankId::C && offset == banks::c_bank::user_binary_inputs) row.source = mapped_bits(config.mapping.user_inputs);
  if (bank == BankId::C && offset == banks::c_bank::user_binary_outputs)
    row.source = mapped_bits(config.mapping.user_outputs);
  add(rows, std::move(row), &reg, shape);
  return 1;
}

}  // namespace

std::string_view part_name(RowPart part) {
  switch (part) {
    case RowPart::word: return "word";
    case RowPart::low: return "low";
    case RowPart::high: return "high";
    case RowPart::pair: return "pair";
    case RowPart::byte_low: return "byte_low";
    case RowPart::byte_high: return "byte_high";
  }
  return "?";
}

std::string_view word_order(const MapRow& row) {
  const bool of_a_pair = row.part == RowPart::low || row.part == RowPart::high || row.part == RowPart::pair;
  return of_a_pair ? "low_first" : "";
}

std::string bits_of(const MapRow& row) {
  if (row.part == RowPart::byte_low) return "7..0";
  if (row.part == RowPart::byte_high) return "15..8";
  return {};
}

std::vector<MapRow> register_map(const Config& config, MapShape shape) {
  const auto shapes = bank_shapes(config);
  const auto write_access = config.modbus.readable_write_banks ? "RW" : "W";
  std::vector<MapRow> rows;
  const auto map = address_map(config);
  for (const auto& window : map.windows()) {
    if (window.kind == banks::Window::Kind::read_block) {
      auto row = row_of(window.first, "read", 0, fmt::format("read_block_0x{:04x}", window.first), "", "analog", "", 1.0,
                        "R", window.source.text);
      const auto* reg = source_register(shapes, window.source);
      if (reg) describe(row, *reg);
      add(rows, std::move(row), reg, shape);
      continue;
    }
    if (window.kind == banks::Window::Kind::write_block) {
      // User analog outputs in tenths, which a master may write below zero as into W.
      rows.push_back(row_of(window.first, "write", 0, fmt::format("user_analog_output_{}", window.output),
                            fmt::format("Uživatelský analogový výstup {}", window.output), "analog", "", 0.1, "W",
                            fmt::format("C+0x{:02X}", window.output - 1), "int16"));
      continue;
    }
    const BankId bank = window.bank;
    const auto name = std::string(banks::bank_name(bank));
    std::uint16_t taken = 1;  // registers the last rows took: 2 for a joined pair
    for (std::uint16_t offset = 0; offset < window.count; offset += taken) {
      taken = 1;
      const auto address = static_cast<std::uint16_t>(window.first + offset);
      if (const auto* table = shapes[index_of(bank)].table; table && offset < table->length()) {
        taken = add_table_register(rows, *table, bank, window, offset, config, shape);
        continue;
      }
      if (banks::is_device_bank(bank) && shapes[index_of(bank)].table) {
        // Past the table, inside the D_N window (banks::device_bank_length): a reserve.
        add(rows,
            row_of(address, name, offset, fmt::format("reserve_{:02x}", offset), "Rezerva",
                   std::string(banks::kind_name(RegisterKind::reserve)), "", 1.0, "R", ""),
            nullptr, shape);
        continue;
      }
      switch (bank) {
        case BankId::A: {
          // A holds an analog source (a W entry, and unmapped 0x7FFF) in signed tenths of
          // its unit, anything else as it is.
          auto row = row_of(address, name, offset, fmt::format("a_{:02x}", offset),
                            fmt::format("ModBUS[BankA+{:02X}]", offset), "analog", "", 0.1, "R", "", "int16");
          const RegisterDef* copied = nullptr;
          if (const auto& source = config.mapping.analog[offset]) {
            row.source = source->text;
            if (const auto* reg = source_register(shapes, *source)) {
              const bool converted = reg->kind == RegisterKind::analog && !config.mapping.analog_raw[offset];
              if (converted) {
                row.label = reg->label;
                row.unit = reg->unit;
                row.kind = std::string(banks::kind_name(reg->kind));
              } else {
                describe(row, *reg);
                copied = reg;
              }
            }
            if (config.mapping.analog_raw[offset]) row.source += " (raw)";
          }
          add(rows, std::move(row), copied, shape);
          break;
        }
        case BankId::B:
          rows.push_back(row_of(address, name, offset, "b", "ModBUS[BankB.0-15]", "bits", "", 1.0, "R",
                                mapped_bits(config.mapping.bits)));
          break;
        case BankId::W:
          rows.push_back(row_of(address, name, offset, fmt::format("w_{:02x}", offset),
                                fmt::format("ModBUS[BankW+{:02X}]", offset), "analog", "", 0.1, write_access, "",
                                "int16"));
          break;
        case BankId::X:
          rows.push_back(row_of(address, name, offset, "x", "ModBUS[BankX.0-15]", "bits", "", 1.0, write_access, ""));
          break;
        default:  // a bank whose table this build lacks
          rows.push_back(row_of(address, name, offset, fmt::format("{}_{:02x}", name, offset), "", "analog", "", 1.0,
                                "R", ""));
      }
    }
  }
  return rows;
}

nlohmann::json map_row_json(const MapRow& row) {
  const auto or_null = [](const std::string& text) { return text.empty() ? nlohmann::json() : nlohmann::json(text); };
  return {{"address", fmt::format("0x{:04X}", row.address)},
          {"bank", row.bank},
          {"offset", row.offset},
          {"id", row.id},
          {"label", row.label},
          {"kind", row.kind},
          {"unit", row.unit},
          {"scale", row.scale},
          {"access", row.access},
          {"source", row.source},
          {"data_type", row.data_type},
          {"part", part_name(row.part)},
          {"bits", or_null(bits_of(row))},
          {"partner", row.partner ? nlohmann::json(fmt::format("0x{:04X}", *row.partner)) : nlohmann::json()},
          {"word_order", or_null(std::string(word_order(row)))}};
}

}  // namespace unima::config
