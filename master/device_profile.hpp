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
  SerialDefaults line;
  std::chrono::microseconds min_gap{0};    // between the starts of two frames to the device
  std::chrono::microseconds frame_gap{0};     // silence the device needs between frames
  std::chrono::microseconds byte_timeout{0};  // longest silence it accepts inside a frame
  std::chrono::microseconds min_reply_time{0};  // it never answers sooner: a shorter time-out always fails
  std::vector<ProfilePoint> points;

  const ProfilePoint* find(std::string_view point_name) const;
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
