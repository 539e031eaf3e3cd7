#include "banks/table_reference.hpp"

#include <algorithm>
#include <vector>

#include <fmt/format.h>

#include "banks/bank_id.hpp"
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

void append_note(std::string& note, std::string_view more) {
  if (more.empty()) return;
  if (!note.empty()) note += "; ";
  note += more;
}

std::string only_text(std::string_view variants) {
  return variants.empty() ? std::string() : fmt::format("Only on {}", variants);
}

// What the value model calls the register's own value: a 32-bit pair once by its
// pair's name, a byte pair only by its bytes (the field rows), a reserve never.
std::string register_value_name(const RegisterDef& reg) {
  switch (reg.kind) {
    case RegisterKind::reserve: return "—";
    case RegisterKind::byte_pair: return "its bytes";
    case RegisterKind::u32_low:
    case RegisterKind::u32_high: return fmt::format("`{}`", reg.pair);
    default: return fmt::format("`{}`", reg.id);
  }
}

void write_table(std::string& out, const DeviceTable& table) {
  out += fmt::format("## `{}`", table.id);
  if (!table.devices.empty()) out += fmt::format(" — {}", table.devices);
  out += "\n\n";
  out += fmt::format("Seed 004 §{}. {} registers (offsets 0x00..0x{:02X}).", table.seed_chapter, table.length(),
                     table.length() - 1);
  if (find_device_type(table.id) == &table && table.length() < device_bank_length)
    out += fmt::format(" A D_N bank of this type is still {} registers (seed §6.1): +0x{:02X}..+0x{:02X} read "
                       "0x7FFF, like reserves.",
                       device_bank_length, table.length(), device_bank_length - 1);
  if (!table.aliases.empty()) {
    out += " Also selected as";
    for (std::size_t i = 0; i < table.aliases.size(); ++i)
      out += fmt::format("{} `{}`", i ? "," : "", table.aliases[i]);
    out += ".";
  }
  out += "\n\n| Offset | Identifier | Value (page, MQTT) | Seed label | Kind | Unit | Scale | Note |\n";
  out += "|---|---|---|---|---|---|---|---|\n";
  for (const auto& reg : table.registers) {
    std::string note = only_text(reg.only);
    if (!reg.inferred.empty()) append_note(note, fmt::format("Inferred: {}", reg.inferred));
    const std::string kind = reg.kind == RegisterKind::analog ? (reg.is_signed ? "analog, signed" : "analog, unsigned")
                                                              : std::string(kind_name(reg.kind));
    out += fmt::format("| +0x{:02X} | `{}` | {} | {} | {} | {} | {} | {} |\n", reg.offset, reg.id, register_value_name(reg),
                       cell(reg.label), kind, cell(reg.unit), register_scale(reg), cell(note));
    for (const auto& field : reg.fields) {
      std::string field_note = only_text(field.only);
      if (!field.inferred.empty()) append_note(field_note, fmt::format("Inferred: {}", field.inferred));
      // A byte of a pair is a quantity of its own; bits have no unit.
      const bool byte = reg.kind == RegisterKind::byte_pair;
      out += fmt::format("| {} | `{}` | `{}` | {} | | {} | {} | {} |\n", bits_text(field), field.id,
                         field_value_name(reg, field), cell(field.label), byte ? cell(field.unit) : "",
                         byte ? fmt::format("{}", field.scale) : "", cell(field_note));
    }
  }
  out += "\n";
}

}  // namespace

std::string tables_markdown() {
  std::string out =
      "# Register tables\n\n"
      "Generated from `banks/tables/*.yaml` by `unima-bridge tables`; do not edit by hand (a test\n"
      "compares this file with the data). Offsets are relative to the bank's base address (`banks` in configuration.md).\n"
      "Labels are the seed's Czech text. Physical value = raw × scale, in the unit given; a\n"
      "32-bit pair is (high × 65536 + low) × the low word's scale, so the high word's scale is\n"
      "65536 times that (the seed's \"65536s\"), and the pair = low + high, each × its own scale.\n"
      "An off-line device reads 0x7FFF in analog registers, 0 in bit registers, 0xFFFF in byte\n"
      "pairs, 0x2020 in ASCII pairs and 0xFFFF/0x7FFF in 32-bit low/high words. In the UIS's\n"
      "byte pairs of firing success and knock, a byte of 255 means \"not measured\" (seed §6.2.4.6).\n\n"
      "The column *Value* names what the page, `/api/registers` and the MQTT documents show:\n"
      "a 32-bit pair as one value (both halves name it), a byte pair as one value\n"
      "per byte in the byte's own unit, a bit word as the word and each named bit, reserves\n"
      "never; a value is null when its register reads \"not measured\" (0x7FFF, or 255 in a\n"
      "byte) or its device is off-line. docs/mqtt.md shows a document.\n\n"
      "*Signed* analog values are two's complement (−32768..32767); the seed does not say which\n"
      "are, so the tables mark the quantities that can go below zero: temperatures, active and\n"
      "reactive power, angles, power factor, corrections, regulator outputs, level differences,\n"
      "user analog outputs and IO signals. Bank A converts by this sign. \"Only on\"\n"
      "repeats the seed's footnotes: registers and bits that exist on some variants only (a\n"
      "MicroGEN-CHP lacks the UniGEN-CHP's, a UIS1 has the cylinder masks, …); other variants\n"
      "send 0 or do not send them.\n\n";
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
