#include "banks/device_table.hpp"

#include "banks/bank_id.hpp"
#include "banks/yaml_document.hpp"

#include <yaml-cpp/yaml.h>

#include <charconv>
#include <set>

#include <fmt/format.h>

namespace unima::banks {

std::string_view kind_name(RegisterKind kind) {
  switch (kind) {
    case RegisterKind::analog: return "analog";
    case RegisterKind::bits: return "bits";
    case RegisterKind::u32_low: return "u32_low";
    case RegisterKind::u32_high: return "u32_high";
    case RegisterKind::byte_pair: return "byte_pair";
    case RegisterKind::ascii_pair: return "ascii_pair";
    case RegisterKind::reserve: return "reserve";
  }
  return "?";
}

std::uint16_t offline_value(RegisterKind kind) {
  switch (kind) {
    case RegisterKind::bits: return 0x0000;
    case RegisterKind::byte_pair: return 0xFFFF;   // 255 = not measured, in each byte (UIS)
    case RegisterKind::ascii_pair: return 0x2020;  // two blanks on the NSU2 display
    case RegisterKind::u32_low: return 0xFFFF;     // the pair reads 0x7FFFFFFF
    default: return 0x7FFF;
  }
}

const RegisterDef* DeviceTable::find(std::string_view register_id) const {
  for (const auto& reg : registers)
    if (reg.id == register_id) return &reg;
  return nullptr;
}

std::optional<DeviceTable::BitRef> DeviceTable::find_bit(std::string_view field_id) const {
  for (const auto& reg : registers)
    for (const auto& field : reg.fields)
      if (field.id == field_id && field.first_bit == field.last_bit) return BitRef{reg.offset, field.first_bit};
  return std::nullopt;
}

namespace {

class Parser : public banks::YamlFields<TableError> {
 public:
  using YamlFields::YamlFields;

  RegisterKind kind(const YAML::Node& node) const {
    static constexpr RegisterKind kinds[] = {RegisterKind::analog,    RegisterKind::bits,     RegisterKind::u32_low,
                                             RegisterKind::u32_high,  RegisterKind::byte_pair, RegisterKind::ascii_pair,
                                             RegisterKind::reserve};
    const auto s = node.as<std::string>();
    for (auto k : kinds)
      if (kind_name(k) == s) return k;
    fail(node, fmt::format("unknown kind '{}'", s));
  }

  double scale(const YAML::Node& node, double otherwise) const {
    const auto scale = node["scale"];
    if (!scale) return otherwise;
    try {
      return scale.as<double>();
    } catch (const YAML::Exception&) {
      fail(scale, "scale must be a number");
    }
  }

  Field field(const YAML::Node& node, const RegisterDef& reg) const {
    only_keys(node, {"bits", "id", "label", "inferred", "unit", "scale", "only"});
    Field f;
    f.id = text(node, "id", true);
    f.label = text(node, "label", false);
    f.inferred = text(node, "inferred", false);
    f.only = text(node, "only", false);
    if ((node["unit"] || node["scale"]) && reg.kind != RegisterKind::byte_pair)
      fail(node, "a field has a unit and scale of its own only in a byte_pair");
    f.unit = node["unit"] ? text(node, "unit", false) : reg.unit;
    f.scale = scale(node, reg.scale);
    const auto bits_node = node["bits"];
    if (!bits_node) fail(node, "missing key 'bits'");
    const auto bits = bits_node.as<std::string>();
    const auto dash = bits.find('-');
    unsigned first = 0, last = 0;
    auto parse = [&](std::string_view part, unsigned& out) {
      const auto [end, ec] = std::from_chars(part.data(), part.data() + part.size(), out);
      if (ec != std::errc{} || end != part.data() + part.size() || out > 15)
        fail(bits_node, fmt::format("bits '{}' must be N or N-M with 0 <= N <= M <= 15", bits));
    };
    parse(std::string_view(bits).substr(0, dash), first);
    last = first;
    if (dash != std::string::npos) parse(std::string_view(bits).substr(dash + 1), last);
    if (last < first) fail(bits_node, fmt::format("bits '{}' must be N or N-M with N <= M", bits));
    f.first_bit = static_cast<std::uint8_t>(first);
    f.last_bit = static_cast<std::uint8_t>(last);
    return f;
  }

  RegisterDef reg(const YAML::Node& node) const {
    only_keys(node, {"offset", "id", "label", "kind", "signed", "only", "unit", "scale", "seed_unit", "pair", "fields",
                     "inferred"});
    RegisterDef r;
    if (!node["offset"]) fail(node, "missing key 'offset'");
    r.offset = static_cast<std::uint16_t>(number(node["offset"], max_offset));
    r.id = text(node, "id", true);
    r.label = text(node, "label", false);
    if (!node["kind"]) fail(node, "missing key 'kind'");
    r.kind = kind(node["kind"]);
    r.unit = text(node, "unit", false);
    r.seed_unit = text(node, "seed_unit", false);
    r.pair = text(node, "pair", false);
    r.inferred = text(node, "inferred", false);
    r.only = text(node, "only", false);
    r.scale = scale(node, 1.0);
    if (r.scale <= 0) fail(node["scale"], "scale must be above 0");
    // Bank A converts analog values by their sign (SPEC §1): every analog register says it.
    if (const auto is_signed = node["signed"]) {
      if (r.kind != RegisterKind::analog) fail(is_signed, "'signed' is only for kind analog");
      r.is_signed = boolean(is_signed);
    } else if (r.kind == RegisterKind::analog) {
      fail(node, fmt::format("analog register '{}' needs 'signed: true' or 'signed: false'", r.id));
    }
    if (const auto fields = node["fields"]) {
      if (!fields.IsSequence()) fail(fields, "fields must be a list");
      if (r.kind != RegisterKind::bits && r.kind != RegisterKind::byte_pair && r.kind != RegisterKind::ascii_pair)
        fail(fields, fmt::format("fields are only for kinds bits, byte_pair and ascii_pair, not {}", kind_name(r.kind)));
      for (const auto& f : fields) r.fields.push_back(field(f, r));
    }
    const bool paired = r.kind == RegisterKind::u32_low || r.kind == RegisterKind::u32_high;
    if (paired == r.pair.empty()) fail(node, "'pair' is required exactly for kinds u32_low and u32_high");
    return r;
  }

  DeviceTableHead head(const YAML::Node& root) const {
    DeviceTableHead h;
    h.id = text(root, "id", true);
    if (const auto aliases = root["aliases"]) {
      if (!aliases.IsSequence()) fail(aliases, "aliases must be a list");
      for (const auto& a : aliases) h.aliases.push_back(a.as<std::string>());
    }
    return h;
  }

  DeviceTable table(const YAML::Node& root) const {
    only_keys(root, {"id", "aliases", "devices", "seed_chapter", "registers"});
    DeviceTable t;
    auto h = head(root);
    t.id = std::move(h.id);
    t.aliases = std::move(h.aliases);
    t.devices = text(root, "devices", false);
    t.seed_chapter = text(root, "seed_chapter", false);
    const auto regs = root["registers"];
    if (!regs || !regs.IsSequence() || regs.size() == 0) fail(root, "'registers' must be a non-empty list");
    if (regs.size() > max_table_length) fail(regs, fmt::format("a table has at most {} registers", max_table_length));
    std::set<std::string> ids;
    for (const auto& node : regs) {
      auto r = reg(node);
      if (r.offset != t.registers.size())
        fail(node, fmt::format("offset 0x{:02X} out of order: expected 0x{:02X}", r.offset, t.registers.size()));
      if (!ids.insert(r.id).second) fail(node, fmt::format("duplicate identifier '{}'", r.id));
      for (const auto& f : r.fields)
        if (f.id != r.id && !ids.insert(f.id).second) fail(node, fmt::format("duplicate identifier '{}'", f.id));
      t.registers.push_back(std::move(r));
    }
    for (std::size_t i = 0; i < t.registers.size(); ++i) {
      const auto& r = t.registers[i];
      if (r.kind != RegisterKind::u32_low) continue;
      if (i + 1 >= t.registers.size() || t.registers[i + 1].kind != RegisterKind::u32_high ||
          t.registers[i + 1].pair != r.pair)
        fail(regs[i], fmt::format("u32_low '{}' must be followed by the u32_high of pair '{}'", r.id, r.pair));
    }
    return t;
  }

 private:
  static constexpr unsigned long max_offset = max_table_length - 1;
};

}  // namespace

namespace {

// The text up to the line `registers:`; the whole text when there is none (the full
// parse then names what is missing).
std::string_view head_text(std::string_view yaml_text) {
  if (yaml_text.starts_with("registers:")) return {};
  const auto at = yaml_text.find("\nregisters:");
  return at == std::string_view::npos ? yaml_text : yaml_text.substr(0, at + 1);
}

}  // namespace

DeviceTableHead parse_device_table_head(std::string_view yaml_text, std::string_view origin) {
  return read_yaml_document<TableError>(head_text(yaml_text), origin, [&](const YAML::Node& root) {
    const Parser parser(origin);
    if (!root.IsMap()) parser.fail(root, "expected a mapping");
    return parser.head(root);
  });
}

DeviceTable parse_device_table(std::string_view yaml_text, std::string_view origin) {
  return read_yaml_document<TableError>(yaml_text, origin,
                                       [&](const YAML::Node& root) { return Parser(origin).table(root); });
}

std::string pair_label(const std::string& low_word_label) {
  const auto comma = low_word_label.rfind(", ");
  return comma == std::string::npos ? low_word_label : low_word_label.substr(0, comma);
}

double register_scale(const RegisterDef& reg) {
  constexpr double high_word_weight = 65536.0;
  return reg.kind == RegisterKind::u32_high ? reg.scale * high_word_weight : reg.scale;
}

std::string field_value_name(const RegisterDef& reg, const Field& field) {
  const auto prefix = reg.id + "_";
  const bool prefixed = field.id.starts_with(prefix) && field.id.size() > prefix.size();
  return reg.id + "." + (prefixed ? field.id.substr(prefix.size()) : field.id);
}

}  // namespace unima::banks
