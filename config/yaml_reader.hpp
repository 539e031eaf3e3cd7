#pragma once
// Checked reading of YAML nodes: every value goes through here, so every error names the
// file, line and column of the offending node (yaml-cpp marks are 0-based, ours 1-based).

#include <yaml-cpp/yaml.h>

#include <initializer_list>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "config/config.hpp"

namespace unima::config {

class YamlReader {
 public:
  explicit YamlReader(std::string origin) : origin_(std::move(origin)) {}

  std::string position(const YAML::Node& node) const;
  [[noreturn]] void fail(const YAML::Node& node, std::string_view message) const;

  /// Rejects keys outside `allowed`; a null node counts as an empty mapping.
  void expect_keys(const YAML::Node& map, std::string_view what, std::initializer_list<std::string_view> allowed) const;
  void expect_keys(const YAML::Node& map, std::string_view what, std::span<const std::string_view> allowed) const;

  /// Decimal or 0x hex, within [min, max].
  unsigned long number(const YAML::Node& node, unsigned long min, unsigned long max) const;
  /// A Modbus register address, 0..0xFFFF: every key that holds one reads it here. A
  /// decimal 30001..39999 or 40001..49999 is taken as written, with a warning naming the
  /// address a PLC-style register number means (modbus/plc_numbers); a six-digit one fails
  /// with it.
  std::uint16_t register_address(const YAML::Node& node) const;
  bool boolean(const YAML::Node& node) const;
  /// A finite decimal number such as 0.5 or 2.5e3.
  double decimal(const YAML::Node& node) const;
  std::string text(const YAML::Node& node) const;
  /// "200ms", "1s", "5m", "1h".
  Duration duration(const YAML::Node& node) const;
  /// The same, and "1750us" too, for the timing of a serial line.
  std::chrono::microseconds fine_duration(const YAML::Node& node) const;
  /// Bytes: "1048576", "64k"/"64kB", "10M"/"10MB", "1G"/"1GB" (powers of 1024), within [min, max].
  std::uint64_t byte_size(const YAML::Node& node, std::uint64_t min, std::uint64_t max) const;
  /// One of `choices`; the error lists them.
  std::string choice(const YAML::Node& node, std::initializer_list<std::string_view> choices) const;

  /// Notes "file:line:column: warning: `message`" for config::warnings.
  void warn(const YAML::Node& node, std::string_view message) const;
  std::vector<std::string> take_warnings() { return std::move(warnings_); }

 private:
  std::string origin_;
  // Noted while the nodes are read, which is otherwise const: a warning changes no value read.
  mutable std::vector<std::string> warnings_;
};

}  // namespace unima::config
