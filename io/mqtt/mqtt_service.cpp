#include "io/mqtt/mqtt_service.hpp"

#include <spdlog/spdlog.h>

#include "io/loop_turn.hpp"
#include "io/mqtt/broker_options.hpp"
#include "mqtt/birth.hpp"
#include "mqtt/command.hpp"
#include "mqtt/config_set.hpp"
#include "mqtt/mqtt_status.hpp"
#include "mqtt/response_topic.hpp"
#include "platform/clock_sync.hpp"
#include "platform/log_text.hpp"
#include "platform/peer_warnings.hpp"
#include "platform/utc_time.hpp"
#include "remote/change_answer.hpp"

namespace unima::io {

namespace {

// How soon a broker that does not keep up, or the buffer's start, is looked at again.
constexpr std::chrono::milliseconds document_retry_after{100};

bool same_mqtt_client(const config::Config& a, const config::Config& b) {
  return a.mqtt.has_value() == b.mqtt.has_value() && (!a.mqtt || a.mqtt->same_client(*b.mqtt));
}

}  // namespace

MqttService::MqttService(Runtime& runtime) : runtime_(runtime), timer_(runtime.io) {
  if (const auto& mqtt = runtime.config().mqtt; mqtt && !mqtt->buffer.file.empty()) {
    buffer_ = std::make_unique<HistoryBuffer>(runtime.io, mqtt->buffer.file, mqtt->buffer.max_size);
    history_ = std::make_unique<HistorySender>(*buffer_);
  }
  client_ = make_client(runtime.config());
  lay_out();
  runtime.changes.listen([this] {
    if (started_ && client_) publish();
  });
}

std::unique_ptr<MqttClient> MqttService::make_client(const config::Config& config) {
  if (!config.mqtt) return nullptr;
  const auto& m = *config.mqtt;
  auto options = broker_options(m, "mqtt");
  options.status_topic = m.topic + "/status";
  options.birth_topic = m.topic + "/birth";
  auto client = std::make_unique<MqttClient>(runtime_.io, options);
  client->hold_reading(!command_flow_.reading());  // commands of the client before it may still wait
  client->birth([this] { return last_birth_ = birth(); });
  client->on_connected([this, announcing = client.get()] {
    // Home Assistant's configs before the documents their entities read.
    discovery_.announce(*announcing);
    if (schedule_) schedule_->publish_all();
    // The history waits for the live documents (publish() begins it once they are out).
    if (history_) history_->end();
    history_waits_ = history_ != nullptr;
    publish();
    send_answers();  // those that waited for a window the lost connection never freed
    send_config_answer();
  });
  client->on_acknowledged([this](int mid) {
    if (history_) history_->acknowledged(mid);
    send_answers();
  });
  client->on_drained([this] { send_answers(); });
  if (m.commands)
    client->subscribe(m.topic + "/set/#", [this](const MqttMessage& message) { take_command(message); },
                      MqttClient::Retained::dropped);
  if (mqtt::takes_configs(config)) subscribe_configs(*client, m.topic);
  if (m.discovery)
    client->subscribe(mqtt::home_assistant_status_topic(config), [this, announcing = client.get()](const MqttMessage& message) {
      if (message.payload == "online") discovery_.announce(*announcing);
    });
  return client;
}

// Of the running config: a reload that keeps the client still changes config_sha256.
std::string MqttService::birth() const {
  const auto& config = runtime_.config();
  mqtt::BirthConfig in_force;
  if (runtime_.config_changes) {
    const auto status = runtime_.config_changes->status();
    in_force = {.source = status.source, .number = status.number, .by = status.by, .applied_at = status.applied_at,
                .last_result = {}, .last_reason = {}};
    if (status.last) {
      in_force.last_result = status.last->result;
      in_force.last_reason = status.last->reason;
    }
  }
  return mqtt::birth_document({.version = UNIMA_VERSION,
                               .config_sha256 = config.file_sha256,
                               .started = runtime_.started_utc,
                               .hostname = config.mqtt->host_name,
                               .machine_id = config.mqtt->machine_id,
                               .clock_synced = platform::clock_synchronized(),
                               .config = std::move(in_force)});
}

// After a reload (commit) and after a change from afar ended, whichever way it ended: the
// retained birth always names the config in force — a client kept by the reload republishes
// it, a new one published it when it connected, and nothing is published when nothing changed.
void MqttService::config_in_force_changed() {
  if (!client_ || !client_->connected() || !runtime_.config().mqtt) return;
  auto now = birth();
  if (now == last_birth_) return;
  if (client_->publish(client_->options().birth_topic, now, true)) last_birth_ = std::move(now);
}

void MqttService::lay_out() {
  const auto& running = *runtime_.banks;
  discovery_.serve(mqtt::discovery_messages(running.config, running.value_model));
  if (!running.config.mqtt) {
    banks_.clear();
    schedule_.reset();
    return;
  }
  banks_ = mqtt::published_banks(running.value_model);
  schedule_.emplace(banks_.size(), report::Intervals{.min_interval = running.config.report.min_interval,
                                                     .max_interval = config::max_report_interval(running.config),
                                                     .on_change = running.config.mqtt->on_change});
  measured_ = {};
}

// A command is a Modbus write by other means: it takes the one write path (rights, the
// register space, the state file, UnimaBUS) and is answered once what it kept is durable.
// An MQTT 5 request (Response Topic, Correlation Data) is answered where it asks, with its
// correlation data, when mqtt/response_topic allows it there; any other command, or a
// response topic refused there or by the broker, on `<prefix>/set/result`.
void MqttService::take_command(const MqttMessage& message) {
  if (command_flow_.reading() && later_commands_.empty()) return carry_out(message);
  later_commands_.push_back({std::string(message.topic), std::string(message.payload), message.response_topic,
                             message.correlation_data});
}

void MqttService::carry_out(const MqttMessage& message) {
  const auto topic = message.topic;
  const auto payload = message.payload;
  const auto& running = *runtime_.banks;
  const auto& prefix = running.config.mqtt->topic;
  const auto set = prefix + "/set/";
  if (!topic.starts_with(set) || topic == prefix + "/set/result") return;  // our own results come back too
  const auto result_topic = prefix + "/set/result";
  const auto answer = [this, result_topic, topic = std::string(topic), response_topic = allowed_response_topic(message, "command", result_topic),
                       correlation = message.correlation_data](const std::string& error) {
    answers_.push_back([this, result_topic, response_topic, correlation, result = mqtt::command_result(topic, error)] {
      if (!response_topic.empty() && client_->publish_response(response_topic, result, correlation)) return;
      client_->publish(result_topic, result, false);
    });
    send_answers();
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
  // A line for the first command from the broker in a period, then how many more (issue
  // 43, finding 6: 50,000 commands wrote 150,000 lines).
  platform::note_from_peer("mqtt: commands taken", client_->options().broker(), "mqtt: {} = {} ({})", topic,
                           payload.substr(0, 20), banks::bank_name(command.bank));
  command_flow_.taken();
  follow_command_flow();
  answer_once_durable(runtime_.state.get(), result.kept_as, [this, answer](bool durable) {
    answer(durable ? std::string() : std::string("the state file refused the write: nothing changed"));
    command_flow_.answered();
    follow_command_flow();
  });
}

// Handed to libmosquitto one at a time, while nothing it holds waits for the socket: it
// writes everything it holds in one go (lib/packet_mosq.c, packet__write), and hundreds of
// answers queued behind a full socket kept the loop for milliseconds. What the window, the
// socket or the turn's budget holds back goes when the broker acknowledges, the socket
// drains (on_drained) or the loop comes back to it.
void MqttService::send_answers() {
  if (!client_) return answers_.clear();
  TurnDeadline turn;
  turn.begin();
  while (!answers_.empty() && !client_->backlogged()) {
    const auto send = std::move(answers_.front());
    answers_.pop_front();
    send();
    if (turn.spent() && !answers_.empty()) {
      if (!sending_later_) {
        sending_later_ = true;
        asio::post(runtime_.io, [this, token = guard_.token()] {
          if (!HandlerGuard::alive(token)) return;
          sending_later_ = false;
          send_answers();
        });
      }
      return;
    }
  }
}

void MqttService::follow_command_flow() {
  if (client_) client_->hold_reading(!command_flow_.reading());
  if (command_flow_.reading() && !later_commands_.empty() && !carrying_out_later_) {
    carrying_out_later_ = true;
    // The service may be gone when the loop comes to it (a stop with the handler queued).
    asio::post(runtime_.io, [this, token = guard_.token()] {
      if (HandlerGuard::alive(token)) carry_out_later_commands();
    });
  }
}

// As many as the flow allows, for at most a turn's budget (io/loop_turn.hpp): a Modbus
// request waits for no more.
void MqttService::carry_out_later_commands() {
  carrying_out_later_ = false;
  if (!client_ || !runtime_.config().mqtt || !runtime_.config().mqtt->commands) {
    later_commands_.clear();  // a reload turned commands off: nobody is there to answer them
    return;
  }
  TurnDeadline turn;
  turn.begin();
  while (command_flow_.reading() && !later_commands_.empty()) {
    const auto command = std::move(later_commands_.front());
    later_commands_.pop_front();
    carry_out({command.topic, command.payload, false, command.response_topic, command.correlation_data, {}});
    if (turn.spent()) break;
  }
  follow_command_flow();
}

// The Response Topic of a command or config when the bridge may answer there, else empty
// (`fallback_topic`): a refusal is counted and warned about (the first from the broker in a
// period, then how many more), with the topic cut short, for the log's sake.
std::string MqttService::allowed_response_topic(const MqttMessage& message, std::string_view what,
                                               const std::string& fallback_topic) {
  if (message.response_topic.empty()) return {};
  const auto& mqtt = *runtime_.config().mqtt;
  const auto verdict = mqtt::judge_response_topic(message.response_topic, mqtt);
  if (verdict == mqtt::ResponseTopicVerdict::answer_there) return message.response_topic;
  ++response_topics_refused_;
  platform::warn_from_peer("mqtt: response topics refused", client_->options().broker(),
                           "mqtt: the Response Topic {} of a {} on {} is {}: answered on {} instead",
                           platform::log_safe(std::string_view(message.response_topic).substr(0, 100)), what,
                           platform::log_safe(message.topic), mqtt::verdict_text(verdict), platform::log_safe(fallback_topic));
  return {};
}

// A config on config/set goes to the one flow (io/config_changes), which checks its size,
// its text and the lock-out rule itself. A retained one would be applied again at every
// connection, over whatever came since: it is cleared on the broker (an empty retained
// message, which comes back here as a clearing), counted and warned about, never applied.
void MqttService::take_config(const MqttMessage& message) {
  // One that a reload turning remote_config.mqtt off found on its way.
  if (!mqtt::takes_configs(runtime_.config())) return;
  const auto& prefix = runtime_.config().mqtt->topic;
  const auto topic = mqtt::config_set_topic(prefix);
  switch (mqtt::judge_config_message(message.payload, message.retained)) {
    case mqtt::ConfigMessage::clearing:
      return;
    case mqtt::ConfigMessage::retained:
      ++retained_configs_dropped_;
      client_->publish(topic, "", true);
      platform::warn_from_peer("mqtt: retained configs", client_->options().broker(),
                               "mqtt: a retained config on {} ({} bytes) not applied and cleared: a config is applied once, "
                               "when it is published, never again from the broker's store",
                               platform::log_safe(topic), message.payload.size());
      return;
    case mqtt::ConfigMessage::config:
      break;
  }
  auto result_topic = mqtt::config_result_topic(prefix);
  ConfigAnswer reply{{}, allowed_response_topic(message, "config", result_topic), message.correlation_data, std::move(result_topic)};
  // On the loop, not in libmosquitto's callback: the flow reloads the bridge, which may stop
  // and destroy the very client whose read brought the message.
  asio::post(runtime_.io, [this, token = guard_.token(), text = std::string(message.payload),
                           by = mqtt::config_author(message.user_properties), reply = std::move(reply)]() mutable {
    if (!HandlerGuard::alive(token)) return;
    const auto answered = [this, token, reply](const remote::ChangeAnswer& answer) {
      if (!HandlerGuard::alive(token)) return;
      config_answer_ = reply;
      config_answer_->payload = remote::answer_json(answer);
      send_config_answer();  // on the client there is now
    };
    if (runtime_.config_changes == nullptr)
      return answered({.id = remote::change_id(text), .result = remote::Result::refused, .errors = {},
                       .reason = "this bridge takes no config from afar", .source = remote::Source::mqtt, .by = by});
    runtime_.config_changes->apply(std::move(text), remote::Source::mqtt, std::move(by), answered);
  });
}

void MqttService::send_config_answer() {
  if (!config_answer_ || !client_ || !client_->connected()) return;
  const auto& a = *config_answer_;
  // A Response Topic the new connection cannot take (MQTT 3.1.1 now) falls back too.
  if (!a.response_topic.empty() && client_->publish_response(a.response_topic, a.payload, a.correlation_data))
    return config_answer_.reset();
  if (client_->publish(a.result_topic, a.payload, false)) config_answer_.reset();
}

// Flagged, not dropped by the client: a retained config must reach take_config to be cleared.
void MqttService::subscribe_configs(MqttClient& client, const std::string& prefix) {
  client.subscribe(mqtt::config_set_topic(prefix), [this](const MqttMessage& message) { take_config(message); },
                   MqttClient::Retained::flagged);
}

// A reload that keeps the client may still turn remote_config.mqtt on or off.
void MqttService::follow_remote_config(const config::Config& previous) {
  const auto& now = runtime_.config();
  const bool was = mqtt::takes_configs(previous), is = mqtt::takes_configs(now);
  if (was == is || !client_) return;
  if (is)
    subscribe_configs(*client_, now.mqtt->topic);
  else
    client_->unsubscribe(mqtt::config_set_topic(previous.mqtt->topic));
}

// Armed only when nothing sooner is: a change that may go at once does not wait for it,
// and a wake-up too early finds nothing due and arms again.
void MqttService::wake_at(report::ReportSchedule::Clock::time_point when) {
  if (timer_due_ && *timer_due_ <= when) return;
  timer_due_ = when;
  timer_.expires_at(when);
  timer_.async_wait([this](const boost::system::error_code& ec) {
    if (ec) return;
    timer_due_.reset();
    if (started_ && client_) publish();
  });
}

// SPEC §15: the broker is unreachable once an attempt to reach it failed or the connection
// dropped — not in the moment between the start and the first connection.
bool MqttService::buffering() const { return buffer_ && !client_->connected() && !client_->last_error().empty(); }

void MqttService::publish() {
  if (!client_ || !schedule_) return;
  // Connected or not: a bank that changed while the broker was away keeps its change's time.
  const auto& running = *runtime_.banks;
  std::vector<std::uint64_t> changes;
  changes.reserve(banks_.size());
  for (const auto bank : banks_) changes.push_back(running.store->changes(bank));
  measured_.note(changes, runtime_.changes.changed_at());
  const bool live = client_->connected();
  // A broker that does not keep up gets the latest state once it does, not a queue of states.
  const auto retry_at = report::ReportSchedule::Clock::now() + std::max(schedule_->intervals().min_interval, document_retry_after);
  if (live && client_->backlogged()) return wake_at(retry_at);
  if (!live && !buffering()) {
    // The connection publishes everything when it comes; until then, only the buffer's
    // start (an attempt that fails) is looked for, as often as a document could go.
    if (buffer_) wake_at(retry_at);
    return;
  }
  // Evaluated only for the banks that may go now, and once for every consumer.
  auto& current = *running.values;
  const auto bank_now = [&](std::size_t index) {
    const auto bank = banks_[index];
    return report::ReportSchedule::BankNow{current.of(bank), current.snapshot()[banks::index_of(bank)].online,
                                           running.deadbands.of(bank)};
  };
  const auto due = schedule_->due(changes, report::ReportSchedule::Clock::now(), bank_now);
  const auto& prefix = running.config.mqtt->topic;
  for (const auto index : due) {
    const auto bank = banks_[index];
    const auto document = mqtt::bank_document(*running.value_model.bank(bank), current.of(bank),
                                              current.snapshot()[banks::index_of(bank)].online, measured_.of(index));
    auto text = document.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
    if (live) client_->publish(prefix + "/" + std::string(banks::bank_name(bank)), text, true);
    else buffer_->append(banks::bank_name(bank), std::move(text));
  }
  if (live && std::exchange(history_waits_, false)) history_->begin(*client_, prefix);
  wake_at(schedule_->next_due());
}

void MqttService::start() {
  started_ = true;
  if (!client_) return;
  client_->start();
  publish();
}

void MqttService::stop() {
  started_ = false;
  if (client_) client_->stop();
  timer_.cancel();
  timer_due_.reset();
}

void MqttService::stage(const Banks& next) {
  const auto buffer_of = [](const config::Config& config) {
    return config.mqtt ? config.mqtt->buffer.file : std::string();
  };
  if (next.config.mqtt && buffer_of(next.config) != (buffer_ ? buffer_->path().string() : std::string()))
    spdlog::warn("{}: mqtt.buffer changes at the next start; until then the history goes to {}", next.config.file,
                 buffer_ ? buffer_->path().string() : "no file");
  new_client_ = !same_mqtt_client(runtime_.config(), next.config);
  if (new_client_) next_client_ = make_client(next.config);
}

void MqttService::abandon() {
  next_client_.reset();
  new_client_ = false;
}

void MqttService::commit(const Banks& previous) {
  if (new_client_) {
    if (client_) client_->stop();  // `offline`, a clean goodbye, before the new client says `online`
    if (history_) history_->end();
    client_ = std::move(next_client_);
    new_client_ = false;
    follow_command_flow();  // the commands answered since it was staged
    if (client_ && started_) client_->start();
  } else {
    follow_remote_config(previous.config);
  }
  lay_out();
  if (client_) discovery_.announce(*client_);  // a new client announces when it connects
  if (started_) publish();  // the new layout's documents, all of them
}

void MqttService::probe(remote::ProbeFacts& facts) const {
  if (!runtime_.config().mqtt) return;
  facts.broker = facts.broker.value_or(true) && client_ && client_->connected();
}

void MqttService::describe(status::Document& status) const {
  if (!client_) return;
  const auto& config = *runtime_.config().mqtt;
  const auto& c = client_->counters();
  mqtt::MqttStatus mqtt{.broker = config.broker,
                        .client_id = config.client_id,
                        .topic = config.topic,
                        .connected = client_->connected(),
                        .connections = c.connections,
                        .drops = c.drops,
                        .published = c.published,
                        .session_takeovers = c.session_takeovers,
                        .retained_commands_dropped = c.retained_commands_dropped,
                        .response_topics_refused = response_topics_refused_,
                        .retained_configs_dropped = retained_configs_dropped_,
                        .since = {},
                        .last_takeover = {},
                        .last_error = {},
                        .buffer = {}};
  platform::append_utc_time(mqtt.since, client_->state_since());  // connected since, or not connected since
  if (const auto taken = client_->last_takeover()) platform::append_utc_time(mqtt.last_takeover.emplace(), *taken);
  if (!client_->last_error().empty()) mqtt.last_error = client_->last_error();
  if (buffer_) {
    const auto b = buffer_->counters();
    mqtt.buffer = mqtt::BufferStatus{buffer_->path().string(), b.bytes, b.messages, b.dropped, history_->sent(), b.syncs, b.failures};
  }
  status.mqtt = std::move(mqtt);
}

}  // namespace unima::io
