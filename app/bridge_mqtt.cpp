// The bridge on MQTT (SPEC §12): its client, and what it publishes — every 100 ms the
// banks whose values or on-line state changed, every `period` and after each
// (re)connection all of them. The values are read as Modbus reads them (the register
// space), so a bank's document and a Modbus read never disagree.

#include <fstream>

#include <spdlog/spdlog.h>

#include "app/bridge.hpp"
#include "app/bridge_core.hpp"
#include "banks/register_space.hpp"
#include "config/register_map.hpp"
#include "io/state_file.hpp"
#include "mqtt/command.hpp"

namespace unima::app {

namespace {

std::string first_line_of(const std::string& path) {
  std::ifstream file(path);
  if (!file) throw std::runtime_error(fmt::format("mqtt.password_file {}: cannot be read", path));
  std::string line;
  std::getline(file, line);
  if (!line.empty() && line.back() == '\r') line.pop_back();
  return line;
}

}  // namespace

std::unique_ptr<io::MqttClient> Bridge::make_mqtt(const config::Config& config) {
  if (!config.mqtt) return nullptr;
  const auto& m = *config.mqtt;
  io::MqttClientOptions options;
  options.host = m.endpoint.host;
  options.port = m.endpoint.port;
  options.tls = m.tls;
  options.ca = m.ca;
  options.certificate = m.certificate;
  options.key = m.key;
  options.client_id = m.client_id;
  options.username = m.username;
  if (!m.password_file.empty()) options.password = first_line_of(m.password_file);
  options.version = m.version;
  options.status_topic = m.topic + "/status";
  auto client = std::make_unique<io::MqttClient>(io_, options);
  client->on_connected([this] {
    if (mqtt_schedule_) mqtt_schedule_->publish_all();
    publish_mqtt();
  });
  if (m.commands)
    client->subscribe(m.topic + "/set/#", [this](std::string_view topic, std::string_view payload) { take_command(topic, payload); });
  return client;
}

// A command is a Modbus write by other means: it takes the one write path (rights, the
// register space, the state file, UnimaBUS) and is answered once what it kept is durable.
void Bridge::take_command(std::string_view topic, std::string_view payload) {
  const auto& prefix = core_->config.mqtt->topic;
  const auto set = prefix + "/set/";
  if (!topic.starts_with(set) || topic == prefix + "/set/result") return;  // our own results come back too
  const auto result_topic = prefix + "/set/result";
  const auto answer = [this, result_topic, topic = std::string(topic)](const std::string& error) {
    if (mqtt_) mqtt_->publish(result_topic, mqtt::command_result(topic, error), false);
  };
  const auto parsed = mqtt::parse_command(topic.substr(set.size()), payload);
  if (const auto* error = std::get_if<std::string>(&parsed)) return answer(*error);
  const auto& command = std::get<mqtt::Command>(parsed);
  const auto base = core_->config.bank_bases[banks::index_of(command.bank)];
  auto& writes = *core_->writes;
  const auto result = command.bank == banks::BankId::X
                          ? writes.write_bit(base, command.offset, command.value != 0, nullptr)
                          : writes.write_registers(static_cast<std::uint16_t>(base + command.offset),
                                                   std::span(&command.value, 1), nullptr);
  if (result.status != modbus::WriteResult::Status::written)
    return answer(fmt::format("{} is not writable in this config", banks::bank_name(command.bank)));
  spdlog::info("mqtt: {} = {} ({})", topic, payload.substr(0, 20), banks::bank_name(command.bank));
  io::answer_once_durable(state_.get(), result.kept_as, [answer](bool durable) {
    answer(durable ? std::string() : std::string("the state file could not be written: the value is not kept"));
  });
}

void Bridge::lay_out_mqtt() {
  if (!core_->config.mqtt) {
    mqtt_layouts_.clear();
    mqtt_schedule_.reset();
    return;
  }
  mqtt_layouts_ = mqtt::bank_layouts(register_rows_, core_->config.mapping);
  mqtt_schedule_.emplace(mqtt_layouts_.size(), core_->config.mqtt->period, core_->config.mqtt->on_change);
}

void Bridge::mqtt_tick() {
  mqtt_timer_.expires_after(mqtt::PublishSchedule::min_interval);
  mqtt_timer_.async_wait([this](const boost::system::error_code& ec) {
    if (ec || !started_ || !mqtt_) return;
    publish_mqtt();
    mqtt_tick();
  });
}

void Bridge::publish_mqtt() {
  // A broker that does not keep up gets the latest state once it does, not a queue of states.
  if (!mqtt_ || !mqtt_->connected() || mqtt_->backlogged() || !mqtt_schedule_) return;
  std::vector<std::optional<std::uint16_t>> values(register_rows_.size());
  for (std::size_t i = 0; i < register_rows_.size(); ++i) {
    std::uint16_t value = 0;
    if (core_->space->read(register_rows_[i].address, std::span(&value, 1))) values[i] = value;
  }
  // Each bank's state as one string of its raw values and on-line flag: compared whole.
  std::vector<std::string> states;
  std::vector<bool> online;
  for (const auto& layout : mqtt_layouts_) {
    const auto bank = banks::parse_bank_name(layout.bank);
    const bool is_station = bank && (banks::is_device_bank(*bank) || banks::is_module_bank(*bank));
    online.push_back(!is_station || core_->store->online(*bank));
    std::string state(1, online.back() ? '1' : '0');
    for (const auto& reg : layout.registers) {
      const auto& v = values[reg.row];
      state += v ? fmt::format("{:04X}", *v) : std::string("----");
    }
    states.push_back(std::move(state));
  }
  const auto now = std::chrono::system_clock::now();
  const auto& prefix = core_->config.mqtt->topic;
  for (const auto index : mqtt_schedule_->due(states, mqtt::PublishSchedule::Clock::now())) {
    const auto& layout = mqtt_layouts_[index];
    const auto document = mqtt::bank_document(layout, values, online[index], now);
    mqtt_->publish(prefix + "/" + layout.bank, document.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace), true);
  }
}

}  // namespace unima::app
