#include "banks/table_reference.hpp"

#include <algorithm>
#include <vector>

#include <fmt/format.h>

#include "banks/table_catalog.hpp"

namespace unima::banks {

namespace {

std::string cell(std::string_view text) {
  std::string out;
  for (char c : text) out += c == '|' ? std::string("\\|") : std::string(1, c);
  return out;
}

std::string bits_text(const Field& f) {
  return f.first_bit == f.last_bit ? fmt::format(".{}", f.first_bit) : fmt::format(".{}-{}", f.first_bit, f.last_bit);
}

void write_table(std::string& out, const DeviceTable& table) {
  out += fmt::format("## `{}`", table.id);
  if (!table.devices.empty()) out += fmt::format(" — {}", table.devices);
  out += "\n\n";
  out += fmt::format("Seed 004 §{}. {} registers (offsets 0x00..0x{:02X}).", table.seed_chapter, table.length(),
                     table.length() - 1);
  if (!table.aliases.empty()) {
    out += " Also selected as";
    for (std::size_t i = 0; i < table.aliases.size(); ++i)
      out += fmt::format("{} `{}`", i ? "," : "", table.aliases[i]);
    out += ".";
  }
  out += "\n\n| Offset | Identifier | Seed label | Kind | Unit | Scale | Note |\n";
  out += "|---|---|---|---|---|---|---|\n";
  for (const auto& reg : table.registers) {
    std::string note = reg.pair.empty() ? "" : fmt::format("32-bit `{}`", reg.pair);
    if (!reg.inferred.empty()) note += fmt::format("{}Inferred: {}", note.empty() ? "" : "; ", reg.inferred);
    out += fmt::format("| +0x{:02X} | `{}` | {} | {} | {} | {} | {} |\n", reg.offset, reg.id, cell(reg.label),
                       kind_name(reg.kind), cell(reg.unit), reg.scale, cell(note));
    for (const auto& field : reg.fields) {
      const std::string field_note = field.inferred.empty() ? "" : fmt::format("Inferred: {}", field.inferred);
      out += fmt::format("| {} | `{}` | {} | | | | {} |\n", bits_text(field), field.id, cell(field.label),
                         cell(field_note));
    }
  }
  out += "\n";
}

}  // namespace

std::string tables_markdown() {
  std::string out =
      "# Register tables\n\n"
      "Generated from `banks/tables/*.yaml` by `unima-bridge tables`; do not edit by hand (a test\n"
      "compares this file with the data). Offsets are relative to the bank's base address (SPEC §1).\n"
      "Labels are the seed's Czech text. Physical value = raw × scale, in the unit given.\n"
      "An off-line device reads 0x7FFF in analog registers, 0 in bit registers, 0xFFFF in byte\n"
      "pairs, 0x2020 in ASCII pairs and 0xFFFF/0x7FFF in 32-bit low/high words.\n\n";
  out += "Device types (`devices.DN.type`):";
  for (const auto id : device_type_ids()) out += fmt::format(" `{}`", id);
  out += ".\n\n";
  // In the seed's order: bank C (§6.2.3), the device types (§6.2.4.x), the IO module (§6.2.5).
  auto tables = all_tables();
  std::stable_sort(tables.begin(), tables.end(),
                   [](const auto* a, const auto* b) { return a->seed_chapter < b->seed_chapter; });
  for (const auto* table : tables) write_table(out, *table);
  return out;
}

}  // namespace unima::banks
