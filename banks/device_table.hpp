#pragma once
// Register tables of the UnimaBUS devices (seed 004 §6.2.3–§6.2.5), loaded from the data
// files in banks/tables/. The files are the single source of truth: the bank sizes, the
// off-line values, the register map export and docs/registers.md all come from them.

#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace unima::banks {

enum class RegisterKind : std::uint8_t { analog, bits, u32_low, u32_high, byte_pair, ascii_pair, reserve };

std::string_view kind_name(RegisterKind kind);

/// What a register reads while its device is off-line or before a telegram carried it
/// (SPEC §1: analog 0x7FFF, bits 0).
std::uint16_t offline_value(RegisterKind kind);

/// A named bit or bit range of a register (bits "3" or "0-7").
struct Field {
  std::uint8_t first_bit = 0;
  std::uint8_t last_bit = 0;
  std::string id;
  std::string label;
  std::string inferred;
  // A byte of a byte pair may hold another quantity than its sibling (UIS: a cylinder
  // number beside a knock level in 0.78125 %); the register's unit and scale otherwise.
  std::string unit;
  double scale = 1.0;
  std::string only;  // the device variants that have it (seed footnotes), "" for all
};

struct RegisterDef {
  std::uint16_t offset = 0;
  std::string id;
  std::string label;  // the seed's Czech text
  RegisterKind kind = RegisterKind::analog;
  std::string unit;       // unit of raw * scale
  double scale = 1.0;
  std::string seed_unit;  // the seed's unit column as printed
  std::string pair;       // id of the 32-bit quantity, for u32_low / u32_high
  /// Analog only: the raw value is two's complement. The seed never says; the tables mark
  /// the quantities that can go below zero (temperatures, powers, angles, corrections).
  bool is_signed = false;
  std::string only;       // the device variants that have it (seed footnotes), "" for all
  std::vector<Field> fields;
  std::string inferred;   // why the offset was reconstructed, when it was
};

/// The 32-bit quantity a pair's halves make, named after its low half's label: the seed
/// labels each half "<quantity>, <which word>" ("Motohodiny, nižší slovo").
std::string pair_label(const std::string& low_word_label);

/// What one unit of a register's raw value is worth, in the register's unit: the table's
/// scale, which for a 32-bit pair is the whole pair's, times 65536 for its high half
/// (seed §6.2.4: "65536s" for the operating hours, 0.1 kWh × 65536 for the energy).
double register_scale(const RegisterDef& reg);

/// The name a field's value goes by outside Modbus (SPEC §17: the page, MQTT):
/// "knock_rank_1_cylinder" of "knock_rank_1" -> "knock_rank_1.cylinder"; a field whose id
/// does not start with its register's keeps it whole ("status.state").
std::string field_value_name(const RegisterDef& reg, const Field& field);

struct DeviceTable {
  std::string id;
  std::vector<std::string> aliases;
  std::string devices;
  std::string seed_chapter;
  std::vector<RegisterDef> registers;  // offsets 0..length-1, in order

  std::uint16_t length() const { return static_cast<std::uint16_t>(registers.size()); }
  const RegisterDef* find(std::string_view register_id) const;

  struct BitRef {
    std::uint16_t offset;
    std::uint8_t bit;
  };
  /// A single-bit field by its id, for bit sources like `D1.remote_start`.
  std::optional<BitRef> find_bit(std::string_view field_id) const;
};

class TableError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// What identifies a table: the keys before `registers:`, which is all a catalog needs
/// to find a table without parsing its registers.
struct DeviceTableHead {
  std::string id;
  std::vector<std::string> aliases;
};

/// Parses the head of a table file (the text before the line `registers:`); throws
/// TableError like parse_device_table.
DeviceTableHead parse_device_table_head(std::string_view yaml_text, std::string_view origin);

/// Parses and validates one table file; `origin` names it in errors.
/// Throws TableError naming origin, line and column.
DeviceTable parse_device_table(std::string_view yaml_text, std::string_view origin);

}  // namespace unima::banks
