// The bridge on MQTT (SPEC §12): its client, and what it publishes — every 100 ms the
// banks whose values or on-line state changed, every `period` and after each
// (re)connection all of them. The values come from the value model (values/), read from
// the register store that Modbus reads, so a bank's document and a Modbus read never disagree.

#include <fstream>

#include <spdlog/spdlog.h>

#include "app/bridge.hpp"
#include "app/bridge_core.hpp"
#include "banks/register_space.hpp"
#include "io/state_file.hpp"
#include "mqtt/command.hpp"
#include "values/store_snapshot.hpp"

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
    mqtt_banks_.clear();
    mqtt_schedule_.reset();
    return;
  }
  mqtt_banks_ = mqtt::published_banks(value_model_);
  mqtt_schedule_.emplace(mqtt_banks_.size(), core_->config.mqtt->period, core_->config.mqtt->on_change);
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
  const auto snapshot = values::snapshot_of(*core_->store);
  // Each bank's state as the text of its values and on-line flag: compared whole.
  std::vector<std::vector<values::Value>> bank_values;
  std::vector<std::string> states;
  for (const auto bank : mqtt_banks_) {
    bank_values.push_back(value_model_.evaluate(bank, snapshot));
    const auto state = mqtt::bank_values(*value_model_.bank(bank), bank_values.back(), snapshot[banks::index_of(bank)].online);
    states.push_back(state.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace));
  }
  const auto now = std::chrono::system_clock::now();
  const auto& prefix = core_->config.mqtt->topic;
  for (const auto index : mqtt_schedule_->due(states, mqtt::PublishSchedule::Clock::now())) {
    const auto bank = mqtt_banks_[index];
    const auto document =
        mqtt::bank_document(*value_model_.bank(bank), bank_values[index], snapshot[banks::index_of(bank)].online, now);
    mqtt_->publish(prefix + "/" + std::string(banks::bank_name(bank)),
                   document.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace), true);
  }
}

}  // namespace unima::app
