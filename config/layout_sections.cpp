// Where the banks are and what they hold (banks, devices, mapping), and the address map
// they make with the read and write blocks: each served window, none overlapping.

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "banks/table_catalog.hpp"
#include "config/section_parsers.hpp"

namespace unima::config {

namespace sections {

namespace {

void parse_mapping_list(const ParseState& state, const YAML::Node& node, std::string_view what, SourceUse use,
                        std::array<std::optional<banks::SourceRef>, banks::Mapping::entries>& entries) {
  const auto& yaml = state.yaml;
  if (!node.IsSequence()) yaml.fail(node, fmt::format("mapping.{} must be a list of sources", what));
  if (node.size() > entries.size())
    yaml.fail(node, fmt::format("mapping.{} has {} entries; there are {}", what, node.size(), entries.size()));
  for (std::size_t n = 0; n < node.size(); ++n)
    if (!node[n].IsNull()) entries[n] = parse_source(state, node[n], use);  // ~ leaves an entry unmapped
}

// Bank A's entries: a source, converted to tenths of its unit, or `{ source: …, raw: true }`
// copied unchanged (SPEC §1).
void parse_analog_mapping(const ParseState& state, const YAML::Node& node, banks::Mapping& m) {
  const auto& yaml = state.yaml;
  if (!node.IsSequence()) yaml.fail(node, "mapping.A must be a list of sources");
  if (node.size() > m.analog.size())
    yaml.fail(node, fmt::format("mapping.A has {} entries; there are {}", node.size(), m.analog.size()));
  for (std::size_t n = 0; n < node.size(); ++n) {
    const auto& entry = node[n];
    if (entry.IsNull()) continue;  // ~ leaves an entry unmapped
    if (!entry.IsMap()) {
      m.analog[n] = parse_source(state, entry, SourceUse::analog);
      continue;
    }
    yaml.expect_keys(entry, fmt::format("mapping.A entry {}", n), {"source", "raw"});
    if (!entry["source"]) yaml.fail(entry, "a mapping.A entry written as a map needs a source, e.g. { source: D1+0x02, raw: true }");
    m.analog[n] = parse_source(state, entry["source"], SourceUse::analog);
    if (entry["raw"]) m.analog_raw[n] = yaml.boolean(entry["raw"]);
  }
}

}  // namespace

banks::SourceRef parse_source(const ParseState& state, const YAML::Node& node, SourceUse use) {
  auto parsed = parse_source_ref(state.yaml.text(node), state.shapes, use);
  if (auto* error = std::get_if<std::string>(&parsed)) state.yaml.fail(node, *error);
  return std::get<banks::SourceRef>(std::move(parsed));
}

void parse_bank_bases(ParseState& state, const YAML::Node& node) {
  const auto& yaml = state.yaml;
  if (!node.IsMap()) yaml.fail(node, "banks must map bank names (A, B, C, D1..D4, S1..S7, W, X) to addresses");
  for (const auto& entry : node) {
    const auto name = entry.first.Scalar();
    const auto bank = banks::parse_bank_name(name);
    if (!bank) yaml.fail(entry.first, fmt::format("unknown bank '{}' (banks are A, B, C, D1..D4, S1..S7, W, X)", name));
    state.config.bank_bases[index_of(*bank)] = yaml.register_address(entry.second);
    state.config.bank_origins[index_of(*bank)] = yaml.position(entry.second);
  }
}

void parse_devices(ParseState& state, const YAML::Node& node) {
  const auto& yaml = state.yaml;
  auto& devices = state.config.devices;
  if (!node.IsMap()) yaml.fail(node, "devices must map D1..D4 to { type, address }");
  for (const auto& entry : node) {
    const auto name = entry.first.Scalar();
    const auto bank = banks::parse_bank_name(name);
    if (!bank || !banks::is_device_bank(*bank))
      yaml.fail(entry.first, fmt::format("unknown device bank '{}' (device banks are D1, D2, D3, D4)", name));
    const auto& dev = entry.second;
    yaml.expect_keys(dev, fmt::format("devices.{}", name), {"type", "address"});
    if (!dev["type"]) yaml.fail(dev, fmt::format("devices.{} needs a type", name));
    if (!dev["address"]) yaml.fail(dev, fmt::format("devices.{} needs the device's UnimaBUS address", name));
    DeviceConfig device;
    const auto type = yaml.text(dev["type"]);
    device.table = banks::find_device_type(type);
    if (!device.table)
      yaml.fail(dev["type"], fmt::format("unknown device type '{}' (known: {})", type,
                                         fmt::join(banks::device_type_ids(), ", ")));
    device.address = static_cast<std::uint8_t>(yaml.number(dev["address"], 0, 255));
    // A D_N is identified by its type and address (SPEC §6): a unit's CHP controller, USC
    // and UVR share its address, but two of one type there could not be told apart.
    for (unsigned n = 1; n <= 4; ++n) {
      const auto& other = devices[n - 1];
      if (other && other->table == device.table && other->address == device.address)
        yaml.fail(dev, fmt::format("devices.{} and devices.D{} are both a {} at UnimaBUS address {}: a D_N is "
                                   "identified by its type and address, so telegrams could not tell them apart",
                                   name, n, device.table->id, device.address));
    }
    devices[banks::bank_number(*bank) - 1] = device;
  }
}

void parse_mapping(ParseState& state, const YAML::Node& node) {
  state.yaml.expect_keys(node, "mapping", {"A", "B", "user_inputs", "user_outputs"});
  auto& m = state.config.mapping;
  if (node["A"]) parse_analog_mapping(state, node["A"], m);
  if (node["B"]) parse_mapping_list(state, node["B"], "B", SourceUse::bit, m.bits);
  if (node["user_inputs"]) parse_mapping_list(state, node["user_inputs"], "user_inputs", SourceUse::bit, m.user_inputs);
  if (node["user_outputs"]) parse_mapping_list(state, node["user_outputs"], "user_outputs", SourceUse::bit, m.user_outputs);
}

void validate_layout(const ParseState& state, const YAML::Node& root) {
  try {
    (void)address_map(state.config);
  } catch (const banks::OverlapError& e) {
    const std::string message = e.what();
    // The windows the file set carry their position; when none did, point at the file.
    if (message.starts_with(state.config.file + ":")) throw ConfigError(message);
    throw ConfigError(fmt::format("{}: {}", state.yaml.position(root), message));
  }
}

}  // namespace sections

banks::BankShapes bank_shapes(const Config& config) {
  std::array<const banks::DeviceTable*, 4> tables{};
  for (std::size_t i = 0; i < 4; ++i)
    if (config.devices[i]) tables[i] = config.devices[i]->table;
  return banks::standard_shapes(tables, banks::io_module_table(), banks::bridge_internal_table());
}

banks::AddressMap address_map(const Config& config) {
  const auto shapes = bank_shapes(config);
  std::vector<banks::Window> windows;
  for (banks::BankId bank : banks::all_banks) {
    const auto length = shapes[index_of(bank)].length;
    if (length == 0) continue;
    banks::Window w;
    w.kind = banks::Window::Kind::bank;
    w.bank = bank;
    w.first = config.bank_bases[index_of(bank)];
    w.count = length;
    w.name = fmt::format("bank {}", banks::bank_name(bank));
    w.origin = config.bank_origins[index_of(bank)];
    windows.push_back(std::move(w));
  }
  for (const Block* block : config.active_blocks()) {
    if (block->type != Block::Type::read && block->type != Block::Type::write) continue;
    banks::Window w;
    w.kind = block->type == Block::Type::read ? banks::Window::Kind::read_block : banks::Window::Kind::write_block;
    w.first = block->reg;
    w.count = 1;
    if (block->source) w.source = *block->source;
    w.output = static_cast<std::uint8_t>(block->output);
    w.name = fmt::format("{} block 0x{:04X}", block_type_name(block->type), block->reg);
    w.origin = block->origin;
    windows.push_back(std::move(w));
  }
  return banks::AddressMap(std::move(windows));
}

}  // namespace unima::config
