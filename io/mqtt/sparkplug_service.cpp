#include "io/mqtt/sparkplug_service.hpp"

#include <charconv>

#include <fmt/ranges.h>
#include <spdlog/spdlog.h>

#include "io/durable_file.hpp"
#include "io/mqtt/broker_options.hpp"
#include "io/state_file.hpp"
#include "platform/clock_sync.hpp"
#include "platform/log_text.hpp"
#include "platform/peer_warnings.hpp"
#include "platform/utc_time.hpp"
#include "sparkplug/edge_status.hpp"

namespace unima::io {

namespace {

// How soon a broker that does not keep up is looked at again (or min_interval, if longer).
constexpr std::chrono::milliseconds sparkplug_retry_after{10};

// Writes of the bdSeq file waiting for the worker: one per CONNECT, and CONNECTs are a
// second apart at least (MqttClient's back-off).
constexpr std::size_t bd_seq_writes_queued = 4;

bool same_sparkplug_client(const config::Config& a, const config::Config& b) {
  return a.sparkplug.has_value() == b.sparkplug.has_value() && (!a.sparkplug || a.sparkplug->same_client(*b.sparkplug));
}

std::uint64_t ms_since_epoch(std::chrono::system_clock::time_point time) {
  return static_cast<std::uint64_t>(std::chrono::duration_cast<std::chrono::milliseconds>(time.time_since_epoch()).count());
}

std::uint64_t now_ms() { return ms_since_epoch(std::chrono::system_clock::now()); }

std::filesystem::path bd_seq_file_of(const config::Config& config) {
  if (config.state.file.empty()) return {};
  return config.state.file + ".sparkplug-bdseq";
}

// The last bdSeq kept, as its decimal number and a line end; a file that holds anything
// else is logged and counts from 0, as a first start does.
std::optional<std::uint64_t> read_bd_seq(const std::filesystem::path& file) {
  if (file.empty()) return std::nullopt;
  try {
    const auto text = read_if_present(file);
    if (!text) return std::nullopt;
    std::uint64_t value = 256;
    const auto* end = text->data() + text->size();
    const auto [rest, ec] = std::from_chars(text->data(), end, value);
    if (ec == std::errc() && value < 256 && (rest == end || *rest == '\n')) return value;
    spdlog::warn("sparkplug: {} holds no bdSeq (0..255); counting from 0", file.string());
  } catch (const std::exception& e) {
    spdlog::warn("sparkplug: {} {}; counting bdSeq from 0", file.string(), e.what());
  }
  return std::nullopt;
}

// `report` as Sparkplug's devices follow it: on change always (mqtt.publish.on_change is MQTT's).
report::Intervals intervals_of(const config::Config& config) {
  return {.min_interval = config.report.min_interval, .max_interval = config::max_report_interval(config), .on_change = true};
}

sparkplug::EdgeSession session_of(const config::Config& config, std::optional<std::uint64_t> last_bd_seq) {
  const auto& s = *config.sparkplug;
  return sparkplug::EdgeSession({s.group_id, s.edge_node_id, !s.primary_host.empty(), intervals_of(config)}, last_bd_seq);
}

}  // namespace

SparkplugService::SparkplugService(Runtime& runtime)
    : runtime_(runtime), due_timer_(runtime.io), rebirth_timer_(runtime.io), bd_seq_writer_(runtime.io, bd_seq_writes_queued) {
  runtime.changes.listen([this, alive = alive_] {
    if (*alive) banks_changed();
  });
  const auto& config = runtime.config();
  if (!config.sparkplug) return;
  bd_seq_file_ = bd_seq_file_of(config);
  session_.emplace(session_of(config, read_bd_seq(bd_seq_file_)));
  client_ = make_client(config);
}

std::unique_ptr<MqttClient> SparkplugService::make_client(const config::Config& config) {
  if (!config.sparkplug) return nullptr;
  const auto& s = *config.sparkplug;
  auto client = std::make_unique<MqttClient>(runtime_.io, broker_options(s, "sparkplug"));
  client->will_for_each_connect([this](MqttClient::WillReady ready) { will_of_next_connect(std::move(ready)); });
  client->on_connected([this] {
    session_->connected();
    publish_due();
  });
  using sparkplug::EdgeSession;
  const auto take = [this](const MqttMessage& message) { take_message(message.topic, message.payload); };
  client->subscribe(EdgeSession::node_topic(s.group_id, "NCMD", s.edge_node_id), take, MqttClient::Retained::dropped);
  client->subscribe(EdgeSession::node_topic(s.group_id, "DCMD", s.edge_node_id) + "/+", take, MqttClient::Retained::dropped);
  if (!s.primary_host.empty()) client->subscribe(sparkplug::EdgeSession::host_state_topic(s.primary_host), take);
  return client;
}

// Each CONNECT counts a bdSeq, kept before the CONNECT goes: the NDEATH the broker may send
// for this connection names it, and so does the next start's first NBIRTH + 1. The write
// and its fdatasync run on the worker; the CONNECT waits for them, the loop does not. The
// worker takes jobs in order, so the file ends with the newest bdSeq.
void SparkplugService::will_of_next_connect(MqttClient::WillReady ready) {
  const auto bd_seq = session_->begin_connect();
  auto death = session_->death(now_ms());
  MqttClient::Will will{std::move(death.topic), std::move(death.payload), 1, false};
  if (bd_seq_file_.empty()) return ready(std::move(will));
  auto failure = std::make_shared<std::string>();
  auto write = [file = bd_seq_file_, bd_seq, failure] {
    try {
      replace_file(file, std::to_string(bd_seq) + "\n");
    } catch (const std::exception& e) {
      *failure = e.what();
    }
  };
  auto done = [file = bd_seq_file_, bd_seq, failure, ready, will] {
    if (!failure->empty()) spdlog::warn("sparkplug: cannot keep bdSeq {} in {}: {}", bd_seq, file.string(), *failure);
    ready(will);
  };
  if (!bd_seq_writer_.submit(write, done)) {
    // Never with CONNECTs a second apart; were it full, the rule holds on the loop.
    write();
    done();
  }
}

void SparkplugService::take_message(std::string_view topic, std::string_view payload) {
  const auto& config = *runtime_.config().sparkplug;
  if (!config.primary_host.empty() && topic == sparkplug::EdgeSession::host_state_topic(config.primary_host)) {
    const auto trusted_now = platform::clock_synchronized() ? std::optional<std::uint64_t>(now_ms()) : std::nullopt;
    switch (session_->host_state(payload, trusted_now)) {
      case sparkplug::HostVerdict::birth:
        spdlog::info("sparkplug: primary host {} is online: births", platform::log_safe(config.primary_host));
        publish_due();
        break;
      case sparkplug::HostVerdict::death:
        spdlog::info("sparkplug: primary host {} went offline: NDEATH, and connecting again to wait for it",
                     platform::log_safe(config.primary_host));
        // Not inside libmosquitto's callback: the connection is closed from the loop.
        asio::post(runtime_.io, [this, alive = alive_] {
          if (*alive) die_and_reconnect();
        });
        break;
      case sparkplug::HostVerdict::from_the_future:
        platform::warn_from_peer("sparkplug: STATE from the future", client_->options().broker(), "sparkplug: a STATE of primary host {} "
                                 "stamped more than {} s ahead of this clock, ignored", platform::log_safe(config.primary_host),
                                 sparkplug::max_host_clock_lead_ms / 1000);
        break;
      case sparkplug::HostVerdict::none: break;
    }
    return;
  }
  const auto ncmd = session_->node_topic("NCMD");
  const auto dcmd = session_->node_topic("DCMD") + "/";
  if (topic == ncmd) take_command("", topic, payload);
  else if (topic.starts_with(dcmd)) take_command(topic.substr(dcmd.size()), topic, payload);
}

// A DCMD write is a Modbus write by other means: the one write path (read_only, the
// register space, the state file first, then UnimaBUS). Nothing is answered: Sparkplug's
// answer is the DDATA of the value once it changed. It is logged as taken once what it
// kept is durable, as a Modbus write is answered; one the state file refuses changed
// nothing, and is logged and counted as refused.
void SparkplugService::take_command(std::string_view device, std::string_view topic, std::string_view payload) {
  const auto& running = *runtime_.banks;
  const auto& config = *running.config.sparkplug;
  const auto command = session_->command(device, payload, running.value_model, config.commands);
  const auto broker = client_->options().broker();
  if (!command.malformed.empty()) {
    platform::warn_from_peer("sparkplug: malformed commands", broker, "sparkplug: a malformed command on {}, ignored: {}", topic,
                             command.malformed);
    return;
  }
  if (!command.refused.empty())
    platform::warn_from_peer("sparkplug: refused commands", broker, "sparkplug: a command on {} refused: {}", topic,
                             fmt::join(command.refused, "; "));
  if (command.rebirth) rebirth_asked();
  auto& writes = *running.writes;
  bool refused = false;
  for (const auto& write : command.writes) {
    const auto address = static_cast<std::uint16_t>(running.config.bank_bases[banks::index_of(write.bank)] + write.offset);
    const auto result = writes.write_field(address, write.mask, write.raw, nullptr);
    if (result.status != modbus::WriteResult::Status::written) {
      session_->refused_by_write_path();
      session_->resend(write.bank, write.value_index);  // the host is told the value it did not change
      refused = true;
      continue;
    }
    answer_once_durable(runtime_.state.get(), result.kept_as,
                        [this, alive = alive_, bank = write.bank, metric = write.metric, value = write.value,
                         index = write.value_index](bool durable) {
                          if (!*alive) return;
                          if (durable) {
                            spdlog::info("sparkplug: DCMD {}/{} = {}", banks::bank_name(bank),
                                         platform::log_safe(metric), value);
                            return;
                          }
                          spdlog::warn("sparkplug: DCMD {}/{} = {} refused: the state file could not keep it; "
                                       "nothing changed",
                                       banks::bank_name(bank), platform::log_safe(metric), value);
                          if (!session_) return;
                          session_->refused_by_write_path();
                          // The host may show what it asked for: its metric again, as it is.
                          session_->resend(bank, index);
                          publish_due();
                        });
  }
  if (refused) publish_due();
}

// At every change, connected or not: a bank that changed while the node was away is born
// again with the time of its change, not of the birth.
std::vector<std::uint64_t> SparkplugService::note_measured() {
  const auto& running = *runtime_.banks;
  std::vector<std::uint64_t> changes;
  changes.reserve(running.value_model.banks().size());
  for (const auto& layout : running.value_model.banks()) changes.push_back(running.store->changes(layout.bank));
  measured_.note(changes, runtime_.changes.changed_at());
  return changes;
}

void SparkplugService::banks_changed() {
  note_measured();
  if (!started_ || !client_ || !session_ || !session_->born()) return;
  publish_due();
}

// Armed only when nothing sooner is: a change that may go at once does not wait for it,
// and a wake-up too early finds nothing due and arms again.
void SparkplugService::wake_at(sparkplug::EdgeSession::Clock::time_point when) {
  if (timer_due_ && *timer_due_ <= when) return;
  timer_due_ = when;
  due_timer_.expires_at(when);
  due_timer_.async_wait([this](const boost::system::error_code& ec) {
    if (ec) return;
    timer_due_.reset();
    if (started_) publish_due();
  });
}

void SparkplugService::publish_due() {
  if (!client_ || !session_) return;
  if (session_->connected_now() && !client_->connected()) session_->disconnected();
  if (!client_->connected()) return;  // the connection's births take it all
  const auto now = sparkplug::EdgeSession::Clock::now();
  // A broker that does not keep up gets the latest values once it does, not a queue.
  if (client_->backlogged())
    return wake_at(now + std::max<std::chrono::steady_clock::duration>(runtime_.config().report.min_interval, sparkplug_retry_after));
  const auto& running = *runtime_.banks;
  auto& current = *running.values;
  const auto& layouts = running.value_model.banks();
  const auto changes = note_measured();
  // Evaluated only for the devices that may have a message now, and once for every consumer.
  const auto device_now = [&](std::size_t i) {
    const auto& layout = layouts[i];
    return sparkplug::DeviceReading{&layout, current.of(layout.bank), current.snapshot()[banks::index_of(layout.bank)].online,
                                    running.deadbands.of(layout.bank), ms_since_epoch(measured_.of(i))};
  };
  for (const auto& message : session_->step({changes, device_now}, now, now_ms()))
    client_->publish_at_most_once(message.topic, message.payload);
  if (const auto next = session_->next_due()) wake_at(*next);
}

void SparkplugService::publish_death() {
  if (!client_ || !client_->connected() || !session_->born()) return;
  const auto death = session_->death(now_ms());
  client_->publish(death.topic, death.payload, false);
}

void SparkplugService::die_and_reconnect() {
  if (!client_ || !started_) return;
  publish_death();
  client_->stop();
  session_->disconnected();
  client_->start();
}

void SparkplugService::start() {
  started_ = true;
  if (!client_) return;
  client_->start();
}

// A clean goodbye is a death said, not left to the will (which the DISCONNECT cancels).
void SparkplugService::stop() {
  started_ = false;
  if (client_) {
    publish_death();
    client_->stop();
  }
  due_timer_.cancel();
  timer_due_.reset();
  rebirth_timer_.cancel();
}

void SparkplugService::rebirth_asked() {
  switch (rebirth_pacing_.asked(sparkplug::RebirthPacing::Clock::now())) {
    case sparkplug::RebirthPacing::Verdict::now:
      spdlog::info("sparkplug: rebirth requested");
      session_->rebirth();
      publish_due();
      return;
    case sparkplug::RebirthPacing::Verdict::later:
      rebirth_timer_.expires_at(rebirth_pacing_.due_at());
      rebirth_timer_.async_wait([this, alive = alive_](const boost::system::error_code& ec) {
        if (!*alive) return;
        rebirth_pacing_.done(sparkplug::RebirthPacing::Clock::now());  // cancelled too: none stays due
        if (ec || !started_ || !session_) return;
        spdlog::info("sparkplug: rebirth requested (with those asked meanwhile; {} coalesced in all)",
                     rebirth_pacing_.coalesced());
        session_->rebirth();
        publish_due();
      });
      return;
    case sparkplug::RebirthPacing::Verdict::joined: return;
  }
}

void SparkplugService::stage(const Banks& next) {
  new_client_ = !same_sparkplug_client(runtime_.config(), next.config);
  if (new_client_) next_client_ = make_client(next.config);
}

void SparkplugService::abandon() {
  next_client_.reset();
  new_client_ = false;
}

void SparkplugService::commit(const Banks&) {
  const auto& config = runtime_.config();
  measured_ = {};  // another store: its banks' times start again
  bd_seq_file_ = bd_seq_file_of(config);
  if (new_client_) {
    if (client_) {
      publish_death();
      client_->stop();
    }
    const auto last = session_ ? session_->bd_seq() : read_bd_seq(bd_seq_file_);
    if (config.sparkplug) session_.emplace(session_of(config, last));
    else session_.reset();
    client_ = std::move(next_client_);
    new_client_ = false;
    if (client_ && started_) client_->start();
    return;
  }
  // The same broker and node: the banks may have changed, the births say what they are,
  // and the devices' messages follow the new `report` from them on.
  if (session_) {
    session_->reload(intervals_of(config));
    publish_due();
  }
}

void SparkplugService::probe(remote::ProbeFacts& facts) const {
  if (!runtime_.config().sparkplug) return;
  facts.broker = facts.broker.value_or(true) && client_ && client_->connected();
}

void SparkplugService::describe(status::Document& status) const {
  if (!client_ || !session_) return;
  const auto& config = *runtime_.config().sparkplug;
  const auto& c = session_->counters();
  const auto& m = client_->counters();
  sparkplug::EdgeStatus s{.broker = config.broker,
                          .client_id = config.client_id,
                          .group_id = config.group_id,
                          .edge_node_id = config.edge_node_id,
                          .connected = client_->connected(),
                          // The session hears of a lost connection at its next look, which waits
                          // for a change; the status says it now.
                          .born = session_->born() && client_->connected(),
                          .connections = m.connections,
                          .drops = m.drops,
                          .published = m.published,
                          .births = c.births,
                          .data = c.data,
                          .deaths = c.deaths,
                          .commands = {c.taken, c.refused, c.malformed, m.retained_commands_dropped},
                          .rebirths_coalesced = rebirth_pacing_.coalesced(),
                          .bdSeq = session_->bd_seq(),
                          .seq = session_->next_seq(),
                          .since = {},
                          .primary_host = {},
                          .last_error = {}};
  platform::append_utc_time(s.since, client_->state_since());  // connected since, or not connected since
  if (!config.primary_host.empty()) {
    using Host = sparkplug::EdgeSession::HostState;
    const auto host = session_->host();
    s.primary_host = {config.primary_host, host == Host::online ? "online" : host == Host::offline ? "offline" : "unknown"};
  }
  if (!client_->last_error().empty()) s.last_error = client_->last_error();
  status.sparkplug = std::move(s);
}

}  // namespace unima::io
