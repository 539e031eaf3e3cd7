// The register map (`unima-bridge map`), as rows and as JSON (register_map_json.hpp).

#include "config/register_map.hpp"
#include "config/register_map_json.hpp"

#include <algorithm>

#include <fmt/format.h>

namespace unima::config {

namespace {

using banks::BankId;

const banks::RegisterDef* source_register(const banks::BankShapes& shapes, const banks::SourceRef& source) {
  const auto* table = shapes[index_of(source.bank)].table;
  return table && source.offset < table->length() ? &table->registers[source.offset] : nullptr;
}

std::string mapped_bits(const std::array<std::optional<banks::SourceRef>, banks::Mapping::entries>& sources) {
  std::string text;
  for (std::size_t n = 0; n < sources.size(); ++n)
    if (sources[n]) text += fmt::format("{}.{}={}", text.empty() ? "" : " ", n, sources[n]->text);
  return text;
}

MapRow table_row(std::uint16_t address, BankId bank, const banks::RegisterDef& reg, const std::string& access) {
  return MapRow{address, std::string(banks::bank_name(bank)), reg.offset, reg.id, reg.label,
                std::string(banks::kind_name(reg.kind)), reg.unit, reg.scale, access, {}};
}

}  // namespace

std::vector<MapRow> register_map(const Config& config) {
  const auto shapes = bank_shapes(config);
  const auto write_access = config.modbus.readable_write_banks ? "RW" : "W";
  std::vector<MapRow> rows;
  const auto map = address_map(config);
  for (const auto& window : map.windows()) {
    if (window.kind == banks::Window::Kind::read_block) {
      MapRow row{window.first, "read", 0, fmt::format("read_block_0x{:04x}", window.first), "", "analog", "", 1.0,
                 "R", window.source.text};
      if (const auto* reg = source_register(shapes, window.source)) {
        row.label = reg->label;
        row.unit = reg->unit;
        row.scale = reg->scale;
      }
      rows.push_back(std::move(row));
      continue;
    }
    if (window.kind == banks::Window::Kind::write_block) {
      rows.push_back(MapRow{window.first, "write", 0, fmt::format("user_analog_output_{}", window.output),
                            fmt::format("Uživatelský analogový výstup {}", window.output), "analog", "", 0.1, "W",
                            fmt::format("C+0x{:02X}", window.output - 1)});
      continue;
    }
    const BankId bank = window.bank;
    const auto name = std::string(banks::bank_name(bank));
    for (std::uint16_t offset = 0; offset < window.count; ++offset) {
      const auto address = static_cast<std::uint16_t>(window.first + offset);
      if (const auto* table = shapes[index_of(bank)].table; table && offset < table->length()) {
        auto row = table_row(address, bank, table->registers[offset], "R");
        if (bank == BankId::C && offset == banks::c_bank::user_binary_inputs)
          row.source = mapped_bits(config.mapping.user_inputs);
        if (bank == BankId::C && offset == banks::c_bank::user_binary_outputs)
          row.source = mapped_bits(config.mapping.user_outputs);
        rows.push_back(std::move(row));
        continue;
      }
      if (banks::is_device_bank(bank) && shapes[index_of(bank)].table) {
        // Past the table, inside the D_N window (banks::device_bank_length): a reserve.
        rows.push_back(MapRow{address, name, offset, fmt::format("reserve_{:02x}", offset), "Rezerva",
                              std::string(banks::kind_name(banks::RegisterKind::reserve)), "", 1.0, "R", ""});
        continue;
      }
      switch (bank) {
        case BankId::A: {
          MapRow row{address, name, offset, fmt::format("a_{:02x}", offset), fmt::format("ModBUS[BankA+{:02X}]", offset),
                     "analog", "", 0.1, "R", ""};
          if (const auto& source = config.mapping.analog[offset]) {
            row.source = source->text;
            if (const auto* reg = source_register(shapes, *source)) {
              row.label = reg->label;
              row.unit = reg->unit;
              // A holds an analog source in tenths of its unit, anything else as it is.
              const bool converted = reg->kind == banks::RegisterKind::analog && !config.mapping.analog_raw[offset];
              row.scale = converted ? 0.1 : reg->scale;
              row.kind = std::string(banks::kind_name(reg->kind));
            }
            if (config.mapping.analog_raw[offset]) row.source += " (raw)";
          }
          rows.push_back(std::move(row));
          break;
        }
        case BankId::B:
          rows.push_back(MapRow{address, name, offset, "b", "ModBUS[BankB.0-15]", "bits", "", 1.0, "R",
                                mapped_bits(config.mapping.bits)});
          break;
        case BankId::W:
          rows.push_back(MapRow{address, name, offset, fmt::format("w_{:02x}", offset),
                                fmt::format("ModBUS[BankW+{:02X}]", offset), "analog", "", 0.1, write_access, ""});
          break;
        case BankId::X:
          rows.push_back(MapRow{address, name, offset, "x", "ModBUS[BankX.0-15]", "bits", "", 1.0, write_access, ""});
          break;
        default:  // a bank whose table this build lacks
          rows.push_back(MapRow{address, name, offset, fmt::format("{}_{:02x}", name, offset), "", "analog", "", 1.0,
                                "R", ""});
      }
    }
  }
  return rows;
}

nlohmann::json map_row_json(const MapRow& row) {
  return {{"address", fmt::format("0x{:04X}", row.address)},
          {"bank", row.bank},
          {"offset", row.offset},
          {"id", row.id},
          {"label", row.label},
          {"kind", row.kind},
          {"unit", row.unit},
          {"scale", row.scale},
          {"access", row.access},
          {"source", row.source}};
}

}  // namespace unima::config
