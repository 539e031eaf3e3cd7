// The function blocks (SPEC §4, seed §7.1–§7.2): read, write and capture blocks of a
// slave, poll and send blocks of a master, and what a poll or send block reads or writes
// on the foreign slave: a profile point, a PLC operand, or a register.

#include <algorithm>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "config/section_parsers.hpp"
#include "master/plc_operand.hpp"

namespace unima::config::sections {

namespace {

class BlockReader {
 public:
  explicit BlockReader(ParseState& state) : state_(state), yaml_(state.yaml) {}

  void read_all(const YAML::Node& node) {
    if (!node.IsSequence()) yaml_.fail(node, "blocks must be a list");
    std::array<const YAML::Node*, banks::c_bank::user_output_count + 1> output_users{};
    std::vector<YAML::Node> kept;  // output_users points into these
    kept.reserve(node.size());
    for (const auto& item : node) {
      kept.push_back(item);
      const auto& b = kept.back();
      if (!b.IsMap() || !b["type"]) yaml_.fail(b, "a block needs a type: read, write, capture, poll or send");
      const auto type = yaml_.choice(b["type"], {"read", "write", "capture", "poll", "send"});
      Block block;
      block.origin = yaml_.position(b);
      if (type == "read") {
        block.type = Block::Type::read;
        yaml_.expect_keys(b, "a read block", {"type", "register", "source"});
      } else if (type == "write") {
        block.type = Block::Type::write;
        yaml_.expect_keys(b, "a write block", {"type", "register", "output"});
      } else if (type == "capture") {
        block.type = Block::Type::capture;
        yaml_.expect_keys(b, "a capture block", {"type", "device", "register", "output", "line"});
      } else if (type == "poll") {
        block.type = Block::Type::poll;
        yaml_.expect_keys(b, "a poll block", {"type", "device", "register", "period", "output", "function", "data_type",
                                              "count", "word_order", "scale", "profile", "point", "operand", "line"});
      } else {
        block.type = Block::Type::send;
        yaml_.expect_keys(b, "a send block", {"type", "device", "register", "period", "source", "function", "data_type",
                                              "word_order", "scale", "profile", "point", "operand", "line"});
      }
      const auto required = [&](const char* key) {
        if (!b[key]) yaml_.fail(b, fmt::format("a {} block needs '{}'", type, key));
        return b[key];
      };
      if (block.is_slave_block() || (!b["point"] && !b["operand"]))
        block.reg = yaml_.register_address(required("register"));
      if (block.type == Block::Type::read) block.source = parse_source(state_, required("source"), SourceUse::analog);
      if (block.type == Block::Type::send) (void)required("source");  // parsed with its function, below
      if (block.type == Block::Type::write || block.type == Block::Type::capture || block.type == Block::Type::poll) {
        const auto& out = required("output");
        block.output = static_cast<unsigned>(yaml_.number(out, 1, banks::c_bank::user_output_count));
        if (const auto* other = output_users[block.output])
          yaml_.fail(out, fmt::format("user analog output {} is already the output of the block at {}", block.output,
                                      yaml_.position(*other)));
        output_users[block.output] = &b;
      }
      if (block.type == Block::Type::capture || block.type == Block::Type::poll || block.type == Block::Type::send) {
        block.line = line_of_block(b, block);
        const auto& device = required("device");
        block.device = static_cast<std::uint8_t>(yaml_.number(device, 1, 247));
        if (block.type == Block::Type::capture) capture_device(device, block);
      }
      if (block.type == Block::Type::poll || block.type == Block::Type::send) {
        const auto& period = required("period");
        block.period = yaml_.duration(period);
        if (block.period.count() == 0) yaml_.fail(period, "the period must be longer than 0");
        master_point(b, block);
      }
      state_.config.blocks.push_back(std::move(block));
    }
  }

 private:
  // SPEC §18: a capture block listens on a slave line, poll and send blocks go out on a
  // master line: the one `line:` names, else the only line of that role. Empty when there
  // is none (the block is then inactive, or the master drives modbus.master.tcp).
  std::string line_of_block(const YAML::Node& b, const Block& block) const {
    const auto& modbus = state_.config.modbus;
    const auto role = block.type == Block::Type::capture ? LineRole::slave : LineRole::master;
    const auto type = block_type_name(block.type);
    std::vector<std::string> names;  // the lines of `role`
    for (const auto& line : modbus.lines)
      if (line.role == role) names.push_back(line.name);
    if (const auto line = b["line"]) {
      const auto name = yaml_.text(line);
      const auto* found = modbus.find_line(name);
      if (!found)
        yaml_.fail(line, fmt::format("no line is named '{}' ({} lines: {})", name, line_role_name(role),
                                     names.empty() ? std::string("none") : fmt::format("{}", fmt::join(names, ", "))));
      if (found->role != role)
        yaml_.fail(line, fmt::format("the line {} is a {} line; a {} block goes on a {} line", name,
                                     line_role_name(found->role), type, line_role_name(role)));
      return name;
    }
    if (names.size() > 1)
      yaml_.fail(b, fmt::format("a {} block needs 'line': {} lines are {} lines ({})", type, names.size(),
                                line_role_name(role), fmt::join(names, ", ")));
    return names.empty() ? std::string() : names.front();
  }

  // A capture block listens to another device than the bridge answers as on its line.
  void capture_device(const YAML::Node& device, const Block& block) const {
    const auto* line = state_.config.modbus.find_line(block.line);
    const bool own_line = line && line->key != "modbus.rtu";
    const auto own = own_line ? line->address : state_.config.modbus.address;
    if (block.device == own)
      yaml_.fail(device, fmt::format("a capture block listens to another device; {} is the bridge's own Modbus address "
                                     "({})", block.device, own_line ? line->key + ".address" : "modbus.address"));
  }

  // What a poll or send block reads or writes on the foreign slave: a profile point, or a
  // register with function, data type, word order and scale (SPEC §4 extensions).
  void master_point(const YAML::Node& b, Block& block) {
    const bool poll = block.type == Block::Type::poll;
    const auto device = state_.config.modbus.master.devices.find(block.device);
    const auto* device_profile = device != state_.config.modbus.master.devices.end() ? device->second.profile : nullptr;
    block.profile = b["profile"] ? parse_profile(state_, b["profile"]) : device_profile;
    if (!block.profile) block.profile = profile_of_device_[block.device].first;  // named by an earlier block
    if (b["profile"] && device_profile && block.profile != device_profile)
      yaml_.fail(b["profile"], fmt::format("device {} is a {} (modbus.master.devices.{})", block.device,
                                           device_profile->id, block.device));
    const auto& seen = profile_of_device_[block.device];
    if (block.profile && seen.first && seen.first != block.profile)
      yaml_.fail(b["profile"] ? b["profile"] : b,
                 fmt::format("device {} is a {} in the block at {}", block.device, seen.first->id, seen.second));
    if (block.profile && !seen.first) profile_of_device_[block.device] = {block.profile, block.origin};

    if (b["scale"]) {
      block.scale = yaml_.decimal(b["scale"]);
      if (block.scale == 0) yaml_.fail(b["scale"], "scale must be a number other than 0");
    }
    if (b["point"] && b["operand"]) yaml_.fail(b["operand"], "a block names a 'point' or an 'operand', not both");
    if (b["point"]) point_block(b, block, poll);
    else if (b["operand"]) operand_block(b, block, poll);
    else register_block(b, block, poll);
    if (!poll) send_source(b["source"], block);
  }

  // A coil (function 5) takes a bit source, or a whole register (on when not 0).
  void send_source(const YAML::Node& node, Block& block) const {
    if (block.function == 5) {
      auto parsed = parse_source_ref(yaml_.text(node), state_.shapes, SourceUse::bit);
      if (auto* ref = std::get_if<banks::SourceRef>(&parsed)) {
        block.source = std::move(*ref);
        return;
      }
    }
    block.source = parse_source(state_, node, SourceUse::analog);
  }

  void point_block(const YAML::Node& b, Block& block, bool poll) {
    const auto& point_node = b["point"];
    if (!block.profile)
      yaml_.fail(point_node, fmt::format("a point needs a device profile: set 'profile' here, or "
                                         "modbus.master.devices.{}.profile", block.device));
    for (const char* key : {"register", "data_type", "count", "word_order"})
      if (b[key]) yaml_.fail(b[key], fmt::format("'{}' comes from the profile's point; leave it out", key));
    block.point = yaml_.text(point_node);
    const auto* point = block.profile->find(block.point);
    if (!point)
      yaml_.fail(point_node, fmt::format("profile {} has no point '{}' (`unima-bridge profiles {}` lists them)",
                                         block.profile->id, block.point, block.profile->id));
    if (point->length > 1)
      yaml_.fail(point_node, fmt::format("{} is an area of {} registers from {}; name one of them with 'register' "
                                         "(and 'data_type') instead of 'point'", point->name, point->length, point->reg));
    const auto& functions = poll ? point->read_functions : point->write_functions;
    if (functions.empty())
      yaml_.fail(point_node, fmt::format("{} cannot be {} (the device {} it only)", point->name,
                                         poll ? "read" : "written", poll ? "writes" : "reads"));
    block.function = functions.front();
    if (b["function"]) {
      block.function = static_cast<std::uint8_t>(yaml_.number(b["function"], 1, 127));
      if (std::find(functions.begin(), functions.end(), block.function) == functions.end())
        yaml_.fail(b["function"], fmt::format("{} is {} with function {}, not {}", point->name, poll ? "read" : "written",
                                              fmt::join(functions, " or "), block.function));
    }
    block.reg = point->reg;
    block.data_type = point->type;
    block.count = point->type == master::ValueType::bits ? point->count : 1;
    block.word_order = block.profile->word_order;
    if (!b["scale"]) block.scale = point->scale;
    if (b["scale"] && point->type == master::ValueType::bits) yaml_.fail(b["scale"], "bits are not scaled");
  }

  // A PLC operand (`D200`, `X17`) of the profile's classes: its address and functions come
  // from the class (master/plc_operand); data_type, word_order and function as for a register.
  void operand_block(const YAML::Node& b, Block& block, bool poll) {
    const auto& node = b["operand"];
    if (!block.profile || block.profile->operands.empty())
      yaml_.fail(node, fmt::format("an operand needs the profile of a PLC named by operands (e.g. 'profile: "
                                   "wecon-lx5v'){}", block.profile ? fmt::format("; {} has points", block.profile->id) : ""));
    if (b["register"]) yaml_.fail(b["register"], "'register' comes from the operand; leave it out");
    auto resolved = master::resolve_operand(*block.profile, yaml_.text(node));
    if (const auto* error = std::get_if<std::string>(&resolved)) yaml_.fail(node, *error);
    const auto& operand = std::get<master::ResolvedOperand>(resolved);
    const auto& functions = poll ? operand.operand_class->read_functions : operand.operand_class->write_functions;
    if (functions.empty())
      yaml_.fail(node, fmt::format("{} cannot be written: the PLC's {} are read only ({})", yaml_.text(node),
                                   operand.operand_class->name, operand.operand_class->label));
    block.point = operand.operand_class->format(operand.number);
    block.reg = operand.reg;
    register_block(b, block, poll, &functions);
  }

  // `allowed`: the functions an operand's class takes, the first the default; else the
  // seed's (MBS_F04 reads with function 4, MBS_F06 writes with 6) and the extensions.
  void register_block(const YAML::Node& b, Block& block, bool poll,
                      const std::vector<std::uint8_t>* allowed = nullptr) {
    using master::ValueType;
    block.function = allowed ? allowed->front() : poll ? 4 : 6;
    if (const auto fn = b["function"]) {
      block.function = static_cast<std::uint8_t>(std::stoul(poll ? yaml_.choice(fn, {"1", "2", "3", "4"})
                                                                 : yaml_.choice(fn, {"5", "6", "16"})));
      if (allowed && std::find(allowed->begin(), allowed->end(), block.function) == allowed->end())
        yaml_.fail(fn, fmt::format("{} is {} with function {}, not {}", block.point, poll ? "read" : "written",
                                   fmt::join(*allowed, " or "), block.function));
    } else if (allowed && !poll && block.function == 6 && b["data_type"]) {
      // A 32-bit value goes with function 16 where the class has it.
      const auto type = master::parse_value_type(yaml_.text(b["data_type"]));
      if (type && master::register_span(*type) == 2 &&
          std::find(allowed->begin(), allowed->end(), std::uint8_t{16}) != allowed->end())
        block.function = 16;
    }
    if (block.profile && !block.profile->implements(block.function))
      yaml_.fail(b["function"] ? b["function"] : b,
                 fmt::format("{} does not implement function {} (it implements {}){}", block.profile->id,
                             block.function, fmt::join(block.profile->functions, ", "),
                             b["function"] ? "" : "; set 'function'"));
    const bool bits = block.function == 1 || block.function == 2 || block.function == 5;
    block.data_type = bits ? ValueType::bits : ValueType::word;
    if (const auto type_node = b["data_type"]) {
      const auto name = yaml_.text(type_node);
      const auto type = master::parse_value_type(name);
      if (!type) yaml_.fail(type_node, fmt::format("'{}' is not one of: bits, word, int, dint, dword, real", name));
      const bool fits = bits ? *type == ValueType::bits
                             : *type != ValueType::bits && (block.function != 6 || master::register_span(*type) == 1);
      if (!fits)
        yaml_.fail(type_node, fmt::format("function {} does not {} {}{}", block.function, poll ? "read" : "write", name,
                                          block.function == 6 ? " (function 6 writes one register: word or int)" : ""));
      block.data_type = *type;
    }
    if (const auto count = b["count"]) {
      if (!bits) yaml_.fail(count, "'count' is for bits (functions 1 and 2): how many are read into the output");
      block.count = static_cast<std::uint16_t>(yaml_.number(count, 1, 16));
    }
    block.word_order = block.profile ? block.profile->word_order : master::WordOrder::low_first;
    if (const auto order_node = b["word_order"]) {
      const auto order = master::parse_word_order(yaml_.text(order_node));
      if (!order) yaml_.fail(order_node, fmt::format("'{}' is not one of: low_first, high_first", yaml_.text(order_node)));
      if (master::register_span(block.data_type) != 2)
        yaml_.fail(order_node, "word_order is for the 32-bit types (dint, dword, real)");
      block.word_order = *order;
    }
    if (b["scale"] && bits) yaml_.fail(b["scale"], "bits are not scaled");
    if (std::uint32_t{block.reg} + block.extent() > 0x10000)
      yaml_.fail(b["register"] ? b["register"] : b, "the value runs past register 0xFFFF");
  }

  ParseState& state_;
  const YamlReader& yaml_;
  // The profile of each device the blocks named so far, and the block that named it.
  std::map<std::uint8_t, std::pair<const master::DeviceProfile*, std::string>> profile_of_device_;
};

}  // namespace

void parse_blocks(ParseState& state, const YAML::Node& node) { BlockReader(state).read_all(node); }

}  // namespace unima::config::sections
