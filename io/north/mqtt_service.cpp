#include "io/north/mqtt_service.hpp"

#include <spdlog/spdlog.h>

#include "io/north/broker_options.hpp"
#include "monitor/monitor_line.hpp"
#include "mqtt/command.hpp"
#include "platform/log_text.hpp"
#include "values/store_snapshot.hpp"

namespace unima::io {

namespace {

bool same_client(const config::Config& a, const config::Config& b) {
  return a.mqtt.has_value() == b.mqtt.has_value() && (!a.mqtt || a.mqtt->same_client(*b.mqtt));
}

}  // namespace

MqttService::MqttService(Runtime& runtime) : runtime_(runtime), timer_(runtime.io) {
  client_ = make_client(runtime.config());
  lay_out();
}

std::unique_ptr<MqttClient> MqttService::make_client(const config::Config& config) {
  if (!config.mqtt) return nullptr;
  const auto& m = *config.mqtt;
  auto options = broker_options(m, "mqtt");
  options.status_topic = m.topic + "/status";
  auto client = std::make_unique<MqttClient>(runtime_.io, options);
  client->on_connected([this] {
    if (schedule_) schedule_->publish_all();
    publish();
  });
  if (m.commands)
    client->subscribe(m.topic + "/set/#", [this](std::string_view topic, std::string_view payload) { take_command(topic, payload); });
  return client;
}

void MqttService::lay_out() {
  const auto& running = *runtime_.banks;
  if (!running.config.mqtt) {
    banks_.clear();
    schedule_.reset();
    return;
  }
  banks_ = mqtt::published_banks(running.value_model);
  schedule_.emplace(banks_.size(), running.config.mqtt->period, running.config.mqtt->on_change);
}

// A command is a Modbus write by other means: it takes the one write path (rights, the
// register space, the state file, UnimaBUS) and is answered once what it kept is durable.
void MqttService::take_command(std::string_view topic, std::string_view payload) {
  const auto& running = *runtime_.banks;
  const auto& prefix = running.config.mqtt->topic;
  const auto set = prefix + "/set/";
  if (!topic.starts_with(set) || topic == prefix + "/set/result") return;  // our own results come back too
  const auto result_topic = prefix + "/set/result";
  const auto answer = [this, result_topic, topic = std::string(topic)](const std::string& error) {
    if (client_) client_->publish(result_topic, mqtt::command_result(topic, error), false);
  };
  const auto parsed = mqtt::parse_command(topic.substr(set.size()), payload);
  if (const auto* error = std::get_if<std::string>(&parsed)) return answer(*error);
  const auto& command = std::get<mqtt::Command>(parsed);
  const auto base = running.config.bank_bases[banks::index_of(command.bank)];
  auto& writes = *running.writes;
  const auto result = command.bank == banks::BankId::X
                          ? writes.write_bit(base, command.offset, command.value != 0, nullptr)
                          : writes.write_registers(static_cast<std::uint16_t>(base + command.offset),
                                                   std::span(&command.value, 1), nullptr);
  if (result.status == modbus::WriteResult::Status::read_only)
    return answer("read only: modbus.tcp.read_only is on, no command is taken");
  if (result.status != modbus::WriteResult::Status::written)
    return answer(fmt::format("{} is not writable in this config", banks::bank_name(command.bank)));
  spdlog::info("mqtt: {} = {} ({})", platform::log_safe(topic), platform::log_safe(payload.substr(0, 20)),
               banks::bank_name(command.bank));
  answer_once_durable(runtime_.state.get(), result.kept_as, [answer](bool durable) {
    answer(durable ? std::string() : std::string("the state file refused the write: nothing changed"));
  });
}

void MqttService::tick() {
  timer_.expires_after(mqtt::PublishSchedule::min_interval);
  timer_.async_wait([this](const boost::system::error_code& ec) {
    if (ec || !started_ || !client_) return;
    publish();
    tick();
  });
}

void MqttService::publish() {
  // A broker that does not keep up gets the latest state once it does, not a queue of states.
  if (!client_ || !client_->connected() || client_->backlogged() || !schedule_) return;
  const auto& running = *runtime_.banks;
  const auto snapshot = values::snapshot_of(*running.store);
  // Each bank's state as the text of its values and on-line flag: compared whole.
  std::vector<std::vector<values::Value>> bank_values;
  std::vector<std::string> states;
  for (const auto bank : banks_) {
    bank_values.push_back(running.value_model.evaluate(bank, snapshot));
    const auto state =
        mqtt::bank_values(*running.value_model.bank(bank), bank_values.back(), snapshot[banks::index_of(bank)].online);
    states.push_back(state.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace));
  }
  const auto now = std::chrono::system_clock::now();
  const auto& prefix = running.config.mqtt->topic;
  for (const auto index : schedule_->due(states, mqtt::PublishSchedule::Clock::now())) {
    const auto bank = banks_[index];
    const auto document =
        mqtt::bank_document(*running.value_model.bank(bank), bank_values[index], snapshot[banks::index_of(bank)].online, now);
    client_->publish(prefix + "/" + std::string(banks::bank_name(bank)),
                     document.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace), true);
  }
}

void MqttService::start() {
  started_ = true;
  if (!client_) return;
  client_->start();
  tick();
}

void MqttService::stop() {
  started_ = false;
  if (client_) client_->stop();
  timer_.cancel();
}

void MqttService::stage(const Banks& next) {
  new_client_ = !same_client(runtime_.config(), next.config);
  if (new_client_) next_client_ = make_client(next.config);
}

void MqttService::abandon() {
  next_client_.reset();
  new_client_ = false;
}

void MqttService::commit(const Banks&) {
  if (new_client_) {
    if (client_) client_->stop();  // `offline`, a clean goodbye, before the new client says `online`
    client_ = std::move(next_client_);
    new_client_ = false;
    if (client_ && started_) {
      client_->start();
      tick();
    }
  }
  lay_out();
}

void MqttService::describe(nlohmann::json& status) const {
  if (!client_) return;
  const auto& config = *runtime_.config().mqtt;
  const auto& c = client_->counters();
  nlohmann::json mqtt{{"broker", config.broker},      {"client_id", config.client_id}, {"topic", config.topic},
                      {"connected", client_->connected()}, {"connections", c.connections},  {"drops", c.drops},
                      {"published", c.published}};
  if (const auto since = client_->connected_since()) {
    std::string time;
    monitor::append_utc_time(time, *since);
    mqtt["since"] = time;
  } else {
    mqtt["since"] = nullptr;
  }
  mqtt["last_error"] = client_->last_error().empty() ? nlohmann::json(nullptr) : nlohmann::json(client_->last_error());
  status["mqtt"] = mqtt;
}

}  // namespace unima::io
