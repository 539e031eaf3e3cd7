#include "sparkplug/edge_session.hpp"

#include <algorithm>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "config/config.hpp"
#include "sparkplug/metric_value.hpp"
#include "sparkplug/payload_codec.hpp"
#include "sparkplug/value_metrics.hpp"
#include "values/value_codec.hpp"

namespace unima::sparkplug {

namespace {


std::string encoded(const Payload& payload) {
  const auto bytes = encode_payload(payload);
  return std::string(bytes.begin(), bytes.end());
}

Metric bd_seq_metric(std::uint64_t bd_seq, std::uint64_t now_ms) {
  Metric metric;
  metric.name = "bdSeq";
  metric.timestamp = now_ms;
  metric.datatype = DataType::Int64;
  metric.value = integer_value(DataType::Int64, static_cast<std::int64_t>(bd_seq));
  return metric;
}

// A metric's name as a log line shows it (a host may leave it out).
std::string name_of(const Metric& metric) { return metric.name.value_or("(a metric without a name)"); }

// The datatype a command's metric is sent as: its own, or its birth's when it leaves it out.
DataType commanded_type(const Metric& metric, const values::ValueDef& def) { return metric.datatype.value_or(data_type_of(def)); }

// The number a command's metric sets, in the metric's unit: a Boolean's as 1 or 0, when
// its value is a bit (a bit takes a number too; the codec takes 0 and 1 only).
std::optional<double> commanded_number(const Metric& metric, const values::ValueDef& def) {
  const auto type = commanded_type(metric, def);
  if (type == DataType::Boolean && def.type == values::ValueType::boolean) {
    const auto flag = boolean_of(metric.value, type);
    return flag ? std::optional<double>(*flag ? 1.0 : 0.0) : std::nullopt;
  }
  return number_of(metric.value, type);
}

// Why a command's metric sets nothing `def` can take.
std::string not_a_value_of(const Metric& metric, const values::ValueDef& def) {
  if (def.type != values::ValueType::boolean) return fmt::format("{} is not a number", def.name);
  return fmt::format("{} takes a Boolean (or the number 0 or 1), not a {}", def.name, data_type_name(commanded_type(metric, def)));
}

// A written value as the log shows it: a bit's as the Boolean it was sent as, any other
// as its register.
std::string shown(const values::ValueDef& def, double number, std::uint16_t raw) {
  if (def.type == values::ValueType::boolean) return number != 0 ? "true" : "false";
  return std::to_string(raw);
}

// A D_N or S_N follows a device on the line; the bridge's own banks are always there.
bool may_die(banks::BankId bank) { return banks::is_device_bank(bank) || banks::is_module_bank(bank); }

}  // namespace

EdgeSession::EdgeSession(Settings settings, std::optional<std::uint64_t> last_bd_seq)
    : settings_(std::move(settings)), last_bd_seq_(last_bd_seq) {}

std::string EdgeSession::node_topic(std::string_view type) const { return node_topic(settings_.group_id, type, settings_.edge_node_id); }

std::string EdgeSession::node_topic(std::string_view group_id, std::string_view type, std::string_view edge_node_id) {
  return fmt::format("{}/{}/{}/{}", config::sparkplug_topic_namespace, group_id, type, edge_node_id);
}

std::string EdgeSession::device_topic(std::string_view type, std::string_view device) const {
  return node_topic(type) + "/" + std::string(device);
}

std::string EdgeSession::host_state_topic(std::string_view host) {
  return fmt::format("{}/STATE/{}", config::sparkplug_topic_namespace, host);
}

std::uint64_t EdgeSession::begin_connect() {
  bd_seq_ = last_bd_seq_ ? (*last_bd_seq_ + 1) % 256 : 0;
  last_bd_seq_ = bd_seq_;
  return *bd_seq_;
}

Message EdgeSession::death(std::uint64_t now_ms) const {
  Payload payload;
  payload.timestamp = now_ms;
  payload.metrics.push_back(bd_seq_metric(bd_seq_.value_or(0), now_ms));
  return {node_topic("NDEATH"), encoded(payload)};
}

void EdgeSession::connected() {
  connected_ = true;
  births_due_ = true;
  // The retained STATE comes again with the subscription; until it does, the host is
  // not known to be online, and what was the newest stamp is forgotten: whatever a
  // message once claimed holds for one connection at most.
  host_ = HostState::unknown;
  host_timestamp_.reset();
}

void EdgeSession::disconnected() {
  connected_ = false;
  node_born_ = false;
  births_due_ = true;
  for (auto& device : devices_) device.born = false;
}

HostVerdict EdgeSession::host_state(std::string_view payload, std::optional<std::uint64_t> trusted_now_ms) {
  const auto json = nlohmann::json::parse(payload, nullptr, false);
  if (!json.is_object() || !json.contains("online") || !json["online"].is_boolean()) return HostVerdict::none;
  std::optional<std::uint64_t> timestamp;
  if (json.contains("timestamp") && json["timestamp"].is_number_unsigned()) timestamp = json["timestamp"].get<std::uint64_t>();
  if (timestamp && trusted_now_ms && *timestamp > *trusted_now_ms + max_host_clock_lead_ms) return HostVerdict::from_the_future;
  // A STATE older than one seen is a host's stale message (its will, delivered late).
  if (timestamp && host_timestamp_ && *timestamp < *host_timestamp_) return HostVerdict::none;
  if (timestamp) host_timestamp_ = timestamp;
  const bool online = json["online"].get<bool>();
  host_ = online ? HostState::online : HostState::offline;
  if (online) {
    births_due_ = births_due_ || !node_born_;
    return connected_ && !node_born_ ? HostVerdict::birth : HostVerdict::none;
  }
  return node_born_ ? HostVerdict::death : HostVerdict::none;
}

bool EdgeSession::may_publish() const {
  return connected_ && (!settings_.primary_host || host_ == HostState::online);
}

std::uint64_t EdgeSession::take_seq() { return seq_++; }  // uint8_t: 255 is followed by 0

void EdgeSession::resend(banks::BankId bank, std::size_t value_index) {
  const auto found = std::find_if(devices_.begin(), devices_.end(), [&](const Device& d) { return d.bank == bank; });
  if (found == devices_.end()) return;  // not born yet: its birth will carry every value
  found->resend.push_back(value_index);
  if (schedule_) schedule_->republish(static_cast<std::size_t>(found - devices_.begin()));
}

std::optional<EdgeSession::Clock::time_point> EdgeSession::next_due() const {
  if (!node_born_ || !schedule_) return std::nullopt;
  return schedule_->next_due();
}

Message EdgeSession::birth_of(const DeviceReading& device, Device& state, std::uint64_t now_ms) {
  Payload payload;
  payload.timestamp = now_ms;
  payload.metrics = metrics_of(*device.layout, device.values, device.measured_ms.value_or(now_ms));
  payload.seq = take_seq();
  state.born = true;
  state.sent.assign(device.values.begin(), device.values.end());
  state.resend.clear();
  ++counters_.births;
  return {device_topic("DBIRTH", banks::bank_name(state.bank)), encoded(payload)};
}

Message EdgeSession::device_death(Device& state, std::uint64_t now_ms) {
  Payload payload;
  payload.timestamp = now_ms;
  payload.seq = take_seq();
  state.born = false;
  ++counters_.deaths;
  return {device_topic("DDEATH", banks::bank_name(state.bank)), encoded(payload)};
}

std::vector<Message> EdgeSession::births(const Devices& devices, Clock::time_point now, std::uint64_t now_ms) {
  births_due_ = false;
  node_born_ = true;
  seq_ = 0;
  std::vector<Message> due;
  Payload payload;
  payload.timestamp = now_ms;
  payload.metrics.push_back(bd_seq_metric(bd_seq_.value_or(0), now_ms));
  Metric rebirth;
  rebirth.name = std::string(rebirth_metric);
  rebirth.timestamp = now_ms;
  rebirth.datatype = DataType::Boolean;
  rebirth.value = false;
  payload.metrics.push_back(std::move(rebirth));
  payload.seq = take_seq();
  ++counters_.births;
  due.push_back({node_topic("NBIRTH"), encoded(payload)});
  // A new schedule has every device due in full at its first call: the births are those
  // messages, and each device's min_interval and max_interval count from them.
  const auto count = devices.changes.size();
  std::vector<std::optional<DeviceReading>> readings(count);
  schedule_.emplace(count, settings_.intervals);
  (void)schedule_->due(devices.changes, now, [&](std::size_t i) {
    const auto& device = readings[i].emplace(devices.now(i));
    return report::ReportSchedule::BankNow{device.values, device.online, device.deadbands};
  });
  devices_.clear();
  devices_.reserve(count);
  for (std::size_t i = 0; i < count; ++i) {
    const auto& device = readings[i] ? *readings[i] : readings[i].emplace(devices.now(i));
    auto& state = devices_.emplace_back(Device{device.layout->bank, false, {}, {}});
    due.push_back(birth_of(device, state, now_ms));
    if (may_die(state.bank) && !device.online) due.push_back(device_death(state, now_ms));
  }
  return due;
}

std::optional<Message> EdgeSession::message_of(std::size_t index, const DeviceReading& device, std::uint64_t now_ms) {
  auto& state = devices_[index];
  const bool alive = device.online || !may_die(state.bank);
  if (state.born && !alive) return device_death(state, now_ms);
  if (!state.born) return alive ? std::optional<Message>(birth_of(device, state, now_ms)) : std::nullopt;
  const auto& layout = *device.layout;
  // In full: every metric. For a change: every metric the host has another value of (the
  // schedule judged the deadbands; a move within one rides along), and those to resend.
  const auto carried = schedule_->went_in_full(index) ? changed_values(layout, {}, device.values, {})
                                                      : changed_values(layout, state.sent, device.values, {}, state.resend);
  state.resend.clear();
  if (carried.empty()) return std::nullopt;  // a bank that never dies, whose on-line state alone changed
  Payload payload;
  payload.timestamp = now_ms;
  payload.metrics = metrics_at(layout, device.values, carried, device.measured_ms.value_or(now_ms));
  payload.seq = take_seq();
  state.sent.assign(device.values.begin(), device.values.end());
  ++counters_.data;
  return Message{device_topic("DDATA", banks::bank_name(state.bank)), encoded(payload)};
}

std::vector<Message> EdgeSession::step(const Devices& devices, Clock::time_point now, std::uint64_t now_ms) {
  if (!may_publish()) return {};
  // A value model of another size than the births named: born again.
  if (births_due_ || !schedule_ || devices.changes.size() != devices_.size()) return births(devices, now, now_ms);
  std::vector<std::optional<DeviceReading>> readings(devices.changes.size());
  const auto reading = [&](std::size_t i) -> const DeviceReading& {
    return readings[i] ? *readings[i] : readings[i].emplace(devices.now(i));
  };
  const auto went = schedule_->due(devices.changes, now, [&](std::size_t i) {
    const auto& device = reading(i);
    return report::ReportSchedule::BankNow{device.values, device.online, device.deadbands};
  });
  std::vector<Message> due;
  for (const auto i : went)
    if (auto message = message_of(i, reading(i), now_ms)) due.push_back(std::move(*message));
  return due;
}

Command EdgeSession::command(std::string_view device, std::string_view bytes, const values::ValueModel& model, bool commands) {
  Command command;
  if (bytes.size() > max_command_bytes) {
    command.malformed = fmt::format("{} bytes, more than the {} a command may have", bytes.size(), max_command_bytes);
  } else if (auto decoded = decode_payload(bytes); !decoded.payload) {
    command.malformed = describe(*decoded.error);
  } else if (device.empty()) {
    for (const auto& metric : decoded.payload->metrics) {
      if (metric.name != rebirth_metric) {
        command.refused.push_back(fmt::format("{}: not a node control the bridge has", name_of(metric)));
        continue;
      }
      const auto flag = boolean_of(metric.value, metric.datatype.value_or(DataType::Boolean));
      if (!flag) {
        command.malformed = "Node Control/Rebirth is not a Boolean";
        break;
      }
      if (*flag) command.rebirth = true;
      else command.refused.push_back("Node Control/Rebirth = false asks nothing");
    }
  } else {
    const auto bank = banks::parse_bank_name(device);
    const auto* layout = bank && banks::is_write_bank(*bank) ? model.bank(*bank) : nullptr;
    if (layout == nullptr) {
      for (const auto& metric : decoded.payload->metrics)
        command.refused.push_back(fmt::format("{}: the bridge takes commands to W and X only", name_of(metric)));
    } else {
      command = dcmd(*layout, *decoded.payload, commands);
    }
  }
  if (!command.malformed.empty()) {
    command.rebirth = false;
    command.writes.clear();
    command.refused.clear();
    ++counters_.malformed;
  } else {
    counters_.taken += command.writes.size() + (command.rebirth ? 1 : 0);
    counters_.refused += command.refused.size();
  }
  return command;
}

// A metric of W or X by its birth's name, its value in the metric's unit: the register is
// the value model's way back (values::raw_of), which refuses what would not read back as
// the value written (SPEC §17).
Command EdgeSession::dcmd(const values::BankValues& layout, const Payload& payload, bool commands) {
  Command command;
  for (const auto& metric : payload.metrics) {
    if (!commands) {
      command.refused.push_back(fmt::format("{}: commands are off (sparkplug.commands)", name_of(metric)));
      continue;
    }
    const auto def = std::find_if(layout.values.begin(), layout.values.end(),
                                  [&](const values::ValueDef& d) { return metric.name == d.name; });
    if (def == layout.values.end()) {
      command.refused.push_back(fmt::format("{}: no metric of {}", name_of(metric), banks::bank_name(layout.bank)));
      continue;
    }
    const auto number = commanded_number(metric, *def);
    if (!number) {
      command.malformed = not_a_value_of(metric, *def);
      return command;
    }
    const auto encoded = values::raw_of(*def, *number);
    if (const auto* reason = std::get_if<std::string>(&encoded)) {
      command.refused.push_back(*reason);
      continue;
    }
    const auto raw = std::get<std::uint16_t>(encoded);
    command.writes.push_back({layout.bank, def->offsets.front(), raw, values::word_mask(*def), def->name, shown(*def, *number, raw),
                              static_cast<std::size_t>(def - layout.values.begin())});
  }
  return command;
}

}  // namespace unima::sparkplug
