#include "master/device_profile.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <charconv>
#include <set>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "banks/yaml_document.hpp"
#include "master/embedded_profiles.hpp"
#include "modbus/protocol.hpp"

namespace unima::master {

std::string_view data_table_name(DataTable table) {
  switch (table) {
    case DataTable::coils: return "coils";
    case DataTable::discrete_inputs: return "discrete_inputs";
    case DataTable::holding_registers: return "holding_registers";
    case DataTable::input_registers: return "input_registers";
  }
  return "?";
}

std::optional<DataTable> table_of_function(std::uint8_t fn) {
  switch (fn) {
    case modbus::function::read_coils:
    case modbus::function::write_single_coil:
    case modbus::function::write_multiple_coils: return DataTable::coils;
    case modbus::function::read_discrete_inputs: return DataTable::discrete_inputs;
    case modbus::function::read_holding_registers:
    case modbus::function::write_single_register:
    case modbus::function::write_multiple_registers: return DataTable::holding_registers;
    case modbus::function::read_input_registers: return DataTable::input_registers;
    default: return std::nullopt;
  }
}

std::uint16_t ProfilePoint::extent() const {
  if (type == ValueType::bits) return count;
  return static_cast<std::uint16_t>(length > 1 ? length : register_span(type));
}

bool ProfilePoint::reads_with(std::uint8_t fn) const {
  return std::find(read_functions.begin(), read_functions.end(), fn) != read_functions.end();
}

bool ProfilePoint::writes_with(std::uint8_t fn) const {
  return std::find(write_functions.begin(), write_functions.end(), fn) != write_functions.end();
}

const ProfilePoint* DeviceProfile::find(std::string_view point_name) const {
  for (const auto& p : points)
    if (p.name == point_name) return &p;
  return nullptr;
}

const OperandClass* DeviceProfile::find_operand_class(std::string_view name) const {
  for (const auto& c : operands)
    if (c.name == name) return &c;
  return nullptr;
}

std::string OperandClass::format(unsigned number) const {
  return base == 8 ? fmt::format("{}{:o}", name, number) : fmt::format("{}{}", name, number);
}

bool DeviceProfile::implements(std::uint8_t fn) const {
  return std::find(functions.begin(), functions.end(), fn) != functions.end();
}

std::vector<std::string_view> DeviceProfile::point_names() const {
  std::vector<std::string_view> names;
  for (const auto& p : points) names.push_back(p.name);
  return names;
}

namespace {

class Parser : public banks::YamlFields<ProfileError> {
 public:
  using YamlFields::YamlFields;

  double real(const YAML::Node& node) const {
    try {
      return node.as<double>();
    } catch (const YAML::Exception&) {
      fail(node, "expected a number");
    }
  }

  // "10ms" or "750us".
  std::chrono::microseconds micros(const YAML::Node& node) const {
    const auto s = node.IsScalar() ? node.Scalar() : std::string();
    unsigned long value = 0;
    const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), value);
    const std::string_view unit(end, static_cast<std::size_t>(s.data() + s.size() - end));
    if (ec == std::errc{} && unit == "ms") return std::chrono::milliseconds(value);
    if (ec == std::errc{} && unit == "us") return std::chrono::microseconds(value);
    fail(node, fmt::format("'{}' is not a duration (e.g. 10ms or 750us)", s));
  }

  std::vector<std::uint8_t> functions(const YAML::Node& node) const {
    std::vector<std::uint8_t> list;
    if (node.IsSequence()) {
      for (const auto& f : node) list.push_back(static_cast<std::uint8_t>(number(f, 127)));
    } else {
      list.push_back(static_cast<std::uint8_t>(number(node, 127)));
    }
    return list;
  }

  // An operand number written in `base` ("1777" in octal); false when a digit does not fit.
  static bool parse_in_base(std::string_view text, unsigned base, unsigned& out) {
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), out, static_cast<int>(base));
    return !text.empty() && ec == std::errc{} && end == text.data() + text.size();
  }

  OperandClass operand_class(const YAML::Node& node, const DeviceProfile& profile) const {
    only_keys(node, {"class", "numbering", "range", "table", "offset", "read", "write", "label", "inferred"});
    OperandClass c;
    c.origin = position(node);
    c.name = text(node, "class", true);
    if (c.name.empty() || !std::all_of(c.name.begin(), c.name.end(), [](char ch) { return ch >= 'A' && ch <= 'Z'; }))
      fail(node["class"], "an operand class is written in capital letters, e.g. X or SD");
    const auto numbering = text(node, "numbering", true);
    if (numbering != "octal" && numbering != "decimal") fail(node["numbering"], "numbering is octal or decimal");
    c.base = numbering == "octal" ? 8 : 10;
    const auto range = text(node, "range", true);
    const auto dash = range.find('-');
    if (dash == std::string::npos || !parse_in_base(std::string_view(range).substr(0, dash), c.base, c.first) ||
        !parse_in_base(std::string_view(range).substr(dash + 1), c.base, c.last) || c.last < c.first)
      fail(node["range"], fmt::format("range '{}' must be FIRST-LAST in {}", range, numbering));
    const auto table = text(node, "table", true);
    static constexpr DataTable tables[] = {DataTable::coils, DataTable::discrete_inputs, DataTable::holding_registers,
                                           DataTable::input_registers};
    const auto found = std::find_if(std::begin(tables), std::end(tables), [&](DataTable t) { return data_table_name(t) == table; });
    if (found == std::end(tables))
      fail(node["table"], "table is coils, discrete_inputs, holding_registers or input_registers");
    c.table = *found;
    if (!node["offset"]) fail(node, "missing key 'offset'");
    c.offset = static_cast<std::uint16_t>(number(node["offset"], 0xFFFF));
    if (std::uint32_t{c.offset} + (c.last - c.first) > 0xFFFF) fail(node["range"], "the class runs past address 0xFFFF");
    if (node["read"]) c.read_functions = functions(node["read"]);
    if (node["write"]) c.write_functions = functions(node["write"]);
    if (c.read_functions.empty()) fail(node, "an operand class needs its 'read' functions");
    for (const auto* list : {&c.read_functions, &c.write_functions})
      for (auto fn : *list) {
        if (table_of_function(fn) != c.table || (list == &c.read_functions) != (fn <= 4))
          fail(node[list == &c.read_functions ? "read" : "write"],
               fmt::format("function {} does not {} the {} table", fn, list == &c.read_functions ? "read" : "write",
                           table));
        if (!profile.implements(fn)) fail(node, fmt::format("function {} is not in the profile's functions", fn));
      }
    c.label = text(node, "label", false);
    c.inferred = text(node, "inferred", false);
    return c;
  }

  ProfilePoint point(const YAML::Node& node, const DeviceProfile& profile) const {
    only_keys(node, {"name", "register", "type", "count", "length", "read", "write", "scale", "unit", "label",
                     "description", "inferred", "example"});
    ProfilePoint p;
    p.origin = position(node);
    p.name = text(node, "name", true);
    if (!node["register"]) fail(node, "missing key 'register'");
    p.reg = static_cast<std::uint16_t>(number(node["register"], 0xFFFF));
    const auto type_name = text(node, "type", true);
    const auto type = parse_value_type(type_name);
    if (!type) fail(node["type"], fmt::format("unknown type '{}' (bits, word, int, dint, dword, real)", type_name));
    p.type = *type;
    if (node["count"]) {
      if (p.type != ValueType::bits) fail(node["count"], "'count' is for bits; an area of registers has 'length'");
      p.count = static_cast<std::uint16_t>(number(node["count"], 16));
      if (p.count == 0) fail(node["count"], "count must be 1..16");
    }
    if (node["length"]) {
      if (p.type == ValueType::bits) fail(node["length"], "'length' is for registers; bits read together have 'count'");
      p.length = static_cast<std::uint16_t>(number(node["length"], 0xFFFF));
      if (p.length == 0) fail(node["length"], "length must be at least 1");
    }
    if (node["read"]) p.read_functions = functions(node["read"]);
    if (node["write"]) p.write_functions = functions(node["write"]);
    if (p.read_functions.empty() && p.write_functions.empty()) fail(node, "a point needs 'read' or 'write' functions");
    const bool bits = p.type == ValueType::bits;
    for (auto fn : p.read_functions) {
      const bool fits = bits ? (fn == 1 || fn == 2) : (fn == 3 || fn == 4);
      if (!fits) fail(node["read"], fmt::format("function {} does not read {}", fn, value_type_name(p.type)));
      if (!profile.implements(fn)) fail(node["read"], fmt::format("function {} is not in the profile's functions", fn));
    }
    for (auto fn : p.write_functions) {
      const bool fits = bits ? (fn == 5 || fn == 15) : (fn == 16 || (fn == 6 && register_span(p.type) == 1));
      if (!fits) fail(node["write"], fmt::format("function {} does not write {}", fn, value_type_name(p.type)));
      if (!profile.implements(fn)) fail(node["write"], fmt::format("function {} is not in the profile's functions", fn));
    }
    if (std::uint32_t{p.reg} + p.extent() > 0x10000) fail(node, "the point runs past address 0xFFFF");
    if (node["scale"]) {
      p.scale = real(node["scale"]);
      if (p.scale == 0) fail(node["scale"], "scale must not be 0");
    }
    p.unit = text(node, "unit", false);
    p.label = text(node, "label", false);
    p.description = text(node, "description", false);
    p.inferred = text(node, "inferred", false);
    if (node["example"]) p.example = real(node["example"]);
    return p;
  }

  DeviceProfile profile(const YAML::Node& root) const {
    only_keys(root, {"id", "name", "source", "functions", "word_order", "line", "min_gap", "frame_gap", "byte_timeout",
                     "min_reply_time", "operands", "points"});
    DeviceProfile d;
    d.id = text(root, "id", true);
    d.name = text(root, "name", false);
    d.source = text(root, "source", false);
    if (!root["functions"]) fail(root, "missing key 'functions'");
    d.functions = functions(root["functions"]);
    if (root["word_order"]) {
      const auto order = parse_word_order(text(root, "word_order", true));
      if (!order) fail(root["word_order"], "word_order is low_first or high_first");
      d.word_order = *order;
    }
    if (const auto line = root["line"]) {
      only_keys(line, {"baud", "parity", "stop_bits"});
      d.line.emplace();
      if (line["baud"]) d.line->baud = static_cast<unsigned>(number(line["baud"], 115200));
      const auto parity = text(line, "parity", false);
      if (parity == "none" || parity.empty()) d.line->parity = 'N';
      else if (parity == "even") d.line->parity = 'E';
      else if (parity == "odd") d.line->parity = 'O';
      else fail(line["parity"], "parity is none, even or odd");
      if (line["stop_bits"]) d.line->stop_bits = static_cast<unsigned>(number(line["stop_bits"], 2));
    }
    if (root["min_gap"]) d.min_gap = micros(root["min_gap"]);
    if (root["frame_gap"]) d.frame_gap = micros(root["frame_gap"]);
    if (root["byte_timeout"]) d.byte_timeout = micros(root["byte_timeout"]);
    if (root["min_reply_time"]) d.min_reply_time = micros(root["min_reply_time"]);
    if (const auto operands = root["operands"]) {
      if (!operands.IsSequence() || operands.size() == 0) fail(operands, "'operands' must be a non-empty list");
      for (const auto& node : operands) {
        auto c = operand_class(node, d);
        if (d.find_operand_class(c.name)) fail(node, fmt::format("duplicate operand class '{}'", c.name));
        d.operands.push_back(std::move(c));
      }
    }
    const auto points = root["points"];
    if (!points && !d.operands.empty()) return d;  // a PLC named by its operands only
    if (!points || !points.IsSequence() || points.size() == 0) fail(root, "'points' must be a non-empty list");
    std::set<std::string> names;
    for (const auto& node : points) {
      auto p = point(node, d);
      if (!names.insert(p.name).second) fail(node, fmt::format("duplicate point name '{}'", p.name));
      d.points.push_back(std::move(p));
    }
    return d;
  }

};

}  // namespace

DeviceProfile parse_device_profile(std::string_view yaml_text, std::string_view origin) {
  return banks::read_yaml_document<ProfileError>(yaml_text, origin,
                                                 [&](const YAML::Node& root) { return Parser(origin).profile(root); });
}

const std::vector<DeviceProfile>& all_profiles() {
  static const std::vector<DeviceProfile> profiles = [] {
    std::vector<DeviceProfile> parsed;
    for (const auto& embedded : embedded_profiles())
      parsed.push_back(parse_device_profile(embedded.yaml_text, std::string("master/profiles/").append(embedded.file_name)));
    std::sort(parsed.begin(), parsed.end(), [](const auto& a, const auto& b) { return a.id < b.id; });
    return parsed;
  }();
  return profiles;
}

const DeviceProfile* find_profile(std::string_view id) {
  for (const auto& p : all_profiles())
    if (p.id == id) return &p;
  return nullptr;
}

std::vector<std::string_view> profile_ids() {
  std::vector<std::string_view> ids;
  for (const auto& p : all_profiles()) ids.push_back(p.id);
  return ids;
}

}  // namespace unima::master
