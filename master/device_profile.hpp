#pragma once
// Device profiles of foreign Modbus slaves (SPEC §9): the register maps of seeds 000, 001
// and 002 as data (master/profiles/*.yaml, compiled in), so that a poll or send block can
// name a point (`profile: sic184-v3, point: POS_ACT_INT`) instead of an address and type.
// The simulator of tests/sim serves the same maps. Pure.

#include <chrono>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "master/master_value.hpp"

namespace unima::master {

/// The four data tables of the Modbus data model (Modbus Application Protocol V1.1b3 §4.3).
enum class DataTable : std::uint8_t { coils, discrete_inputs, holding_registers, input_registers };

std::string_view data_table_name(DataTable table);

/// The table a read or write function works on; nullopt for other functions.
std::optional<DataTable> table_of_function(std::uint8_t function);

struct ProfilePoint {
  std::string name;                           // the seed's identifier, e.g. POS_ACT_INT
  std::uint16_t reg = 0;                      // protocol address, 0-based
  ValueType type = ValueType::word;
  std::uint16_t count = 1;                    // bits: coils or inputs read together
  std::uint16_t length = 1;                   // >1: an area of that many registers (user registers)
  std::vector<std::uint8_t> read_functions;   // empty: write-only; the first is the default
  std::vector<std::uint8_t> write_functions;  // empty: read-only; the first is the default
  double scale = 1.0;                         // device value x scale = bridge register
  std::string unit;                           // unit of the bridge register
  std::string label;                          // the seed's text
  std::string description;
  std::string inferred;                       // why something was reconstructed, when it was
  std::optional<double> example;              // a value the seed quotes; the simulator serves it
  std::string origin;                         // "file:line:column" of the point

  /// Registers (or coils) the point covers from reg.
  std::uint16_t extent() const;
  bool reads_with(std::uint8_t function) const;
  bool writes_with(std::uint8_t function) const;
};

/// A class of PLC operands (WECON LX5V, seed 003): `X17`, `Y10` (octal), `M100`, `D200`,
/// each number one cell of a Modbus table from `offset` on (master/plc_operand).
struct OperandClass {
  std::string name;                           // the PLC's letters: X, Y, M, S, T, C, D
  unsigned base = 10;                         // 8: numbered in octal, as X and Y are
  unsigned first = 0;                         // the operand numbers the class has
  unsigned last = 0;
  DataTable table = DataTable::holding_registers;
  std::uint16_t offset = 0;                   // the Modbus address of operand `first`
  std::vector<std::uint8_t> read_functions;   // the first is the default
  std::vector<std::uint8_t> write_functions;  // empty: the PLC's inputs cannot be written
  std::string label;
  std::string inferred;                       // where the offset comes from, when not a manual
  std::string origin;                         // "file:line:column"

  bool bits() const { return table == DataTable::coils || table == DataTable::discrete_inputs; }
  /// `number` written in the class's base (17 for X17 = 15).
  std::string format(unsigned number) const;
};

struct SerialDefaults {
  unsigned baud = 19200;
  char parity = 'N';
  unsigned stop_bits = 1;
};

struct DeviceProfile {
  std::string id;
  std::string name;
  std::string source;                    // which seed
  std::vector<std::uint8_t> functions;   // what the device implements
  WordOrder word_order = WordOrder::low_first;
  std::optional<SerialDefaults> line;  // nullopt: the seed does not say
  std::chrono::microseconds min_gap{0};    // between the starts of two frames to the device
  std::chrono::microseconds frame_gap{0};     // silence the device needs between frames
  std::chrono::microseconds byte_timeout{0};  // longest silence it accepts inside a frame
  std::chrono::microseconds min_reply_time{0};  // it never answers sooner: a shorter time-out always fails
  std::vector<ProfilePoint> points;
  std::vector<OperandClass> operands;  // a PLC's operand classes, when it is named by them

  const ProfilePoint* find(std::string_view point_name) const;
  const OperandClass* find_operand_class(std::string_view name) const;
  bool implements(std::uint8_t function) const;
  std::vector<std::string_view> point_names() const;
};

class ProfileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Parses and validates one profile file; errors name `origin`, line and column.
DeviceProfile parse_device_profile(std::string_view yaml_text, std::string_view origin);

/// Every compiled-in profile, by id. Throws ProfileError if an embedded file is invalid.
const std::vector<DeviceProfile>& all_profiles();
const DeviceProfile* find_profile(std::string_view id);
std::vector<std::string_view> profile_ids();

}  // namespace unima::master
