#include "io/mqtt/mqtt_client.hpp"

#include <mosquitto.h>
#include <mqtt_protocol.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <utility>

#include <spdlog/spdlog.h>

#include "platform/log_text.hpp"
#include "platform/peer_warnings.hpp"

namespace unima::io {

namespace {

using namespace std::chrono_literals;

constexpr std::chrono::milliseconds max_backoff = 60s;

std::string reason(int rc) {
  if (rc == MOSQ_ERR_ERRNO) return std::strerror(errno);
  return mosquitto_strerror(rc);
}

// MQTT 5's Response Topic, Correlation Data and User Properties of a message, when it carries them.
void read_request_properties(const mosquitto_property* properties, MqttMessage& message) {
  char* topic = nullptr;
  if (mosquitto_property_read_string(properties, MQTT_PROP_RESPONSE_TOPIC, &topic, false) != nullptr && topic != nullptr) {
    message.response_topic = topic;
    std::free(topic);
  }
  void* data = nullptr;
  std::uint16_t length = 0;
  if (mosquitto_property_read_binary(properties, MQTT_PROP_CORRELATION_DATA, &data, &length, false) != nullptr && data != nullptr) {
    message.correlation_data.assign(static_cast<const char*>(data), length);
    std::free(data);
  }
  // Each call finds the next one after `property` (skip_first after the first).
  const mosquitto_property* property = properties;
  for (bool skip = false;; skip = true) {
    char* name = nullptr;
    char* value = nullptr;
    property = mosquitto_property_read_string_pair(property, MQTT_PROP_USER_PROPERTY, &name, &value, skip);
    if (property == nullptr) break;
    message.user_properties.emplace_back(name != nullptr ? name : "", value != nullptr ? value : "");
    std::free(name);
    std::free(value);
  }
}

}  // namespace

MqttClient::MqttClient(asio::io_context& io, MqttClientOptions options)
    : io_(io), options_(std::move(options)), resolver_(io), misc_timer_(io), retry_timer_(io) {
  static std::once_flag library;
  std::call_once(library, [] { mosquitto_lib_init(); });
  mosq_ = make_handle();
}

// A handle of its own for each connection: what the last one had queued (QoS 1 messages
// the broker never acknowledged) would be sent again after a reconnect — stale documents
// before the present ones. The present is published in full on each connection instead.
mosquitto* MqttClient::make_handle() {
  auto* mosq = mosquitto_new(options_.client_id.c_str(), true, this);
  if (mosq == nullptr) throw std::runtime_error("mqtt: libmosquitto cannot make a client: " + reason(MOSQ_ERR_ERRNO));
  mosquitto_int_option(mosq, MOSQ_OPT_PROTOCOL_VERSION, options_.version == 5 ? MQTT_PROTOCOL_V5 : MQTT_PROTOCOL_V311);
  // A bounded window of QoS 1 messages in flight: libmosquitto walks the whole list of
  // messages it holds at every PUBACK, and with no bound a burst of commands answered
  // faster than the broker acknowledged them (its PUBACKs queued behind the commands it
  // still had for us) made that list tens of thousands long — seconds of the loop
  // (issue 43, finding 6). Past the window messages wait inside the library, which
  // backlogged() reports, as it does a socket that wants writing.
  mosquitto_max_inflight_messages_set(mosq, static_cast<unsigned>(in_flight_window));
  const std::string offline = "offline";
  if (!options_.status_topic.empty())
    mosquitto_will_set(mosq, options_.status_topic.c_str(), static_cast<int>(offline.size()), offline.data(), 1, true);
  if (!options_.username.empty())
    mosquitto_username_pw_set(mosq, options_.username.c_str(), options_.password.empty() ? nullptr : options_.password.c_str());
  if (options_.tls) {
    const int rc = mosquitto_tls_set(mosq, options_.ca.empty() ? nullptr : options_.ca.c_str(), options_.ca.empty() ? "/etc/ssl/certs" : nullptr,
                                     options_.certificate.empty() ? nullptr : options_.certificate.c_str(),
                                     options_.key.empty() ? nullptr : options_.key.c_str(), nullptr);
    if (rc != MOSQ_ERR_SUCCESS) {
      mosquitto_destroy(mosq);
      throw std::runtime_error("mqtt: TLS files: " + reason(rc));
    }
  }
  mosquitto_connect_callback_set(mosq, [](mosquitto*, void* self, int rc) { static_cast<MqttClient*>(self)->handle_connack(rc); });
  mosquitto_disconnect_callback_set(mosq, [](mosquitto*, void* self, int rc) { static_cast<MqttClient*>(self)->handle_disconnect(rc); });
  mosquitto_publish_callback_set(mosq, [](mosquitto*, void* self, int mid) {
    auto& client = *static_cast<MqttClient*>(self);
    client.unacknowledged_.erase(mid);
    if (client.on_acknowledged_) client.on_acknowledged_(mid);
    client.end_read_when_spent();
  });
  // The v5 callback serves 3.1.1 too (without properties).
  mosquitto_message_v5_callback_set(mosq, [](mosquitto*, void* self, const mosquitto_message* message,
                                             const mosquitto_property* properties) {
    auto& client = *static_cast<MqttClient*>(self);
    if (message->topic == nullptr) return;
    MqttMessage received{message->topic, std::string_view(static_cast<const char*>(message->payload),
                                                          static_cast<std::size_t>(std::max(message->payloadlen, 0))),
                         message->retain, {}, {}, {}};
    read_request_properties(properties, received);
    for (const auto& subscription : client.subscriptions_) {
      bool matches = false;
      mosquitto_topic_matches_sub(subscription.pattern.c_str(), message->topic, &matches);
      if (!matches) continue;
      if (received.retained && subscription.retained == Retained::dropped) {
        client.drop_retained_command(received.topic);
        continue;
      }
      subscription.handler(received);
    }
    client.end_read_when_spent();
  });
  return mosq;
}

MqttClient::~MqttClient() {
  *alive_ = false;
  release_socket();
  mosquitto_destroy(mosq_);  // closes the socket when one is open
}

void MqttClient::start() {
  running_ = true;
  state_since_ = std::chrono::system_clock::now();
  spdlog::info("mqtt: connecting to {}:{} as {}", options_.host, options_.port, options_.client_id);
  resolve();
  tick();
}

// Once a second: libmosquitto's keep-alive (PINGREQ, and a broker silent for too long).
void MqttClient::tick() {
  misc_timer_.expires_after(1s);
  misc_timer_.async_wait([this, alive = alive_](const boost::system::error_code& ec) {
    if (!*alive || ec || !running_) return;
    if (socket_) {
      const int rc = mosquitto_loop_misc(mosq_);
      if (rc != MOSQ_ERR_SUCCESS) lost(reason(rc));
      else watch();
    }
    tick();
  });
}

void MqttClient::stop() {
  if (!running_) return;
  running_ = false;
  ++attempts_;
  misc_timer_.cancel();
  retry_timer_.cancel();
  resolver_.cancel();
  if (connected_) {
    if (!options_.status_topic.empty()) send(options_.status_topic, "offline", true);
    mosquitto_disconnect(mosq_);  // written at once: the broker forgets the will
    connected_ = false;
    spdlog::info("mqtt: disconnected from {}:{}", options_.host, options_.port);
  }
  release_socket();
}

bool MqttClient::backlogged() const {
  return connected_ && (mosquitto_want_write(mosq_) || window_full());
}

void MqttClient::hold_reading(bool held) {
  if (std::exchange(held_, held) == held) return;
  if (!held) watch();
}

bool MqttClient::publish(const std::string& topic, std::string_view payload, bool retain) {
  return connected_ && send(topic, payload, retain);
}

bool MqttClient::send(const std::string& topic, std::string_view payload, bool retain) {
  int mid = 0;
  const int rc = mosquitto_publish(mosq_, &mid, topic.c_str(), static_cast<int>(payload.size()), payload.data(), 1, retain);
  if (rc != MOSQ_ERR_SUCCESS) return false;
  unacknowledged_.insert(mid);
  ++counters_.published;
  watch();
  return true;
}

bool MqttClient::publish_response(const std::string& topic, std::string_view payload, std::string_view correlation_data) {
  if (!connected_) return false;
  mosquitto_property* properties = nullptr;
  if (!correlation_data.empty() &&
      mosquitto_property_add_binary(&properties, MQTT_PROP_CORRELATION_DATA, correlation_data.data(),
                                    static_cast<std::uint16_t>(correlation_data.size())) != MOSQ_ERR_SUCCESS)
    return false;
  // A topic with wildcards, or not UTF-8, is refused here (MOSQ_ERR_INVALID), not sent.
  int mid = 0;
  const int rc = mosquitto_publish_v5(mosq_, &mid, topic.c_str(), static_cast<int>(payload.size()), payload.data(), 1,
                                      false, properties);
  mosquitto_property_free_all(&properties);
  if (rc != MOSQ_ERR_SUCCESS) return false;
  unacknowledged_.insert(mid);
  ++counters_.published;
  watch();
  return true;
}

bool MqttClient::publish_at_most_once(const std::string& topic, std::string_view payload) {
  if (!connected_) return false;
  const int rc = mosquitto_publish(mosq_, nullptr, topic.c_str(), static_cast<int>(payload.size()), payload.data(), 0, false);
  if (rc != MOSQ_ERR_SUCCESS) return false;
  ++counters_.published;
  watch();
  return true;
}

std::optional<int> MqttClient::publish_acknowledged(const std::string& topic, std::string_view payload) {
  if (!connected_) return std::nullopt;
  int mid = 0;
  const int rc = mosquitto_publish(mosq_, &mid, topic.c_str(), static_cast<int>(payload.size()), payload.data(), 1, false);
  if (rc != MOSQ_ERR_SUCCESS) return std::nullopt;
  unacknowledged_.insert(mid);
  ++counters_.published;
  watch();
  return mid;
}

void MqttClient::resolve() {
  resolver_.async_resolve(options_.host, std::to_string(options_.port),
                          [this, alive = alive_](const boost::system::error_code& ec, asio::ip::tcp::resolver::results_type results) {
                            if (!*alive || !running_) return;
                            if (ec || results.empty()) {
                              lost(fmt::format("cannot look up {}: {}", options_.host, ec ? ec.message() : "no address"));
                              return;
                            }
                            connect(results.begin()->endpoint().address().to_string());
                          });
}

void MqttClient::connect(const std::string& address) {
  // mqtts checks the broker's certificate against the name it was given, so it gets the
  // name (libmosquitto looks it up again, a moment after the resolver did); plain MQTT
  // gets the address, and nothing on the loop waits for DNS.
  const auto& host = options_.tls ? options_.host : address;
  if (!make_will_) return connect_now(host);
  make_will_([this, alive = alive_, attempt = ++attempts_, host](const Will& will) {
    if (!*alive || !running_ || attempt != attempts_) return;
    mosquitto_will_set(mosq_, will.topic.c_str(), static_cast<int>(will.payload.size()), will.payload.data(), will.qos, will.retain);
    connect_now(host);
  });
}

void MqttClient::connect_now(const std::string& host) {
  const int rc = mosquitto_connect_async(mosq_, host.c_str(), options_.port, static_cast<int>(options_.keepalive.count()));
  const int fd = mosquitto_socket(mosq_);
  if (rc != MOSQ_ERR_SUCCESS || fd < 0) return lost(reason(rc));
  socket_.emplace(io_, fd);
  read_cut_short_ = false;
  watch();
}

void MqttClient::watch() {
  if (!socket_) return;
  if (!reading_ && !held_ && read_cut_short_) {
    // What the last read left may be in OpenSSL's buffer rather than in the socket, which
    // would then never turn readable: read again at the loop's next turn, not on a wait.
    reading_ = true;
    asio::post(io_, [this, alive = alive_] {
      if (!*alive) return;
      reading_ = false;
      if (socket_ && !held_) read();
    });
  }
  if (!reading_ && !held_) {
    reading_ = true;
    socket_->async_wait(asio::posix::stream_descriptor::wait_read, [this, alive = alive_](const boost::system::error_code& ec) {
      if (!*alive) return;
      reading_ = false;
      // Held after the wait began: the read waits for hold_reading(false), which watches again.
      if (ec || !socket_ || held_) return;
      read();
    });
  }
  if (!writing_ && mosquitto_want_write(mosq_)) {
    writing_ = true;
    socket_->async_wait(asio::posix::stream_descriptor::wait_write, [this, alive = alive_](const boost::system::error_code& ec) {
      if (!*alive) return;
      writing_ = false;
      if (ec || !socket_) return;
      after_io(mosquitto_loop_write(mosq_, 1));
      if (socket_ && !mosquitto_want_write(mosq_) && on_drained_) on_drained_();
    });
  }
}

void MqttClient::read() {
  read_turn_.begin();
  read_cut_short_ = false;
  after_io(mosquitto_loop_read(mosq_, 1));
}

// libmosquitto reads as many packets as it has QoS 1 messages in flight (up to
// in_flight_window), or until the socket is empty, and calls back for each: in a burst
// of commands that kept the loop for milliseconds. Its read loop (lib/loop.c,
// mosquitto_loop_read) ends after a packet when errno is EAGAIN, as after a read that found
// nothing; set here, after a callback, it ends the read once the turn's budget is spent
// (io/loop_turn.hpp). What is left is read at the loop's next turn (watch()).
void MqttClient::end_read_when_spent() {
  if (!read_turn_.spent()) return;
  errno = EAGAIN;
  read_cut_short_ = true;
}

void MqttClient::after_io(int rc) {
  if (rc == MOSQ_ERR_SUCCESS && mosquitto_socket(mosq_) >= 0) return watch();
  lost(rc == MOSQ_ERR_SUCCESS ? std::string("the connection closed") : reason(rc));
}

// libmosquitto has closed the socket (or will, at the next attempt): Asio lets go of it
// without closing, so that a descriptor number reused meanwhile is not touched.
void MqttClient::release_socket() {
  if (!socket_) return;
  socket_->release();
  socket_.reset();
}

std::string MqttClientOptions::broker() const { return fmt::format("{}:{}", host, port); }

void MqttClient::drop_retained_command(std::string_view topic) {
  ++counters_.retained_commands_dropped;
  platform::warn_from_peer("mqtt: retained commands", options_.broker(),
                           "mqtt: a retained command on {} dropped: a command is carried out once, when it is published, "
                           "never again from the broker's store (clear it: publish an empty retained message there)",
                           platform::log_safe(topic));
}

void MqttClient::lost(const std::string& why) {
  release_socket();
  if (connected_) handle_disconnect(MOSQ_ERR_CONN_LOST);
  // Never inside one of libmosquitto's calls: lost() runs after they return.
  mosquitto_destroy(mosq_);
  mosq_ = make_handle();
  unacknowledged_.clear();  // message ids are the old handle's
  last_error_ = taken_over_ ? fmt::format("the broker gave the session of client id {} to another client", options_.client_id)
                            : refusal_.empty() ? why : std::exchange(refusal_, {});
  if (!drop_logged_) {
    spdlog::warn("mqtt: no connection to {}:{}: {}; trying again with back-off", options_.host, options_.port, last_error_);
    drop_logged_ = true;
  }
  retry_later();
}

void MqttClient::retry_later() {
  if (!running_) return;
  std::uniform_real_distribution<double> spread(0.75, 1.25);
  auto wait = std::chrono::milliseconds(static_cast<long>(backoff_.count() * spread(jitter_)));
  backoff_ = std::min(backoff_ * 2, max_backoff);
  if (std::exchange(taken_over_, false)) {
    // No sooner than retry_after: the jitter only adds, so that a pair sharing an id
    // does not come back together.
    std::uniform_real_distribution<double> later(1.0, 1.25);
    const std::chrono::milliseconds hold = mqtt::SessionTakeover::retry_after;
    wait = std::max(wait, std::chrono::milliseconds(static_cast<long>(hold.count() * later(jitter_))));
  }
  retry_timer_.expires_after(wait);
  retry_timer_.async_wait([this, alive = alive_](const boost::system::error_code& ec) {
    if (*alive && !ec && running_) resolve();
  });
}

void MqttClient::handle_connack(int rc) {
  if (rc != 0) {
    // MQTT 5 answers with a reason code, 3.1.1 with a CONNACK code.
    refusal_ = std::string("the broker refused the connection: ") +
               (options_.version == 5 ? mosquitto_reason_string(rc) : mosquitto_connack_string(rc));
    return;  // loop_read reports the refusal as an error: lost() logs it and retries
  }
  drop_logged_ = false;
  last_error_.clear();
  backoff_ = 1s;
  ++counters_.connections;
  state_since_ = std::chrono::system_clock::now();
  takeover_.connected(std::chrono::steady_clock::now());
  spdlog::info("mqtt: connected to {}:{} as {}", options_.host, options_.port, options_.client_id);
  // The birth, then `online`, before anything else (publish() takes nothing until
  // connected_): whoever sees `online` finds the birth of this connection already there.
  if (birth_ && !options_.birth_topic.empty()) send(options_.birth_topic, birth_(), true);
  if (!options_.status_topic.empty()) send(options_.status_topic, "online", true);
  connected_ = true;
  for (const auto& subscription : subscriptions_) send_subscribe(subscription);
  if (on_connected_) on_connected_();
}

void MqttClient::send_subscribe(const Subscription& subscription) {
  if (options_.version == 5 && subscription.retained == Retained::dropped)
    mosquitto_subscribe_v5(mosq_, nullptr, subscription.pattern.c_str(), 1, MQTT_SUB_OPT_SEND_RETAIN_NEVER, nullptr);
  else if (options_.version == 5 && subscription.retained == Retained::flagged)
    mosquitto_subscribe_v5(mosq_, nullptr, subscription.pattern.c_str(), 1, MQTT_SUB_OPT_RETAIN_AS_PUBLISHED, nullptr);
  else
    mosquitto_subscribe(mosq_, nullptr, subscription.pattern.c_str(), 1);
}

void MqttClient::subscribe(std::string pattern, std::function<void(const MqttMessage&)> handler, Retained retained) {
  subscriptions_.push_back({std::move(pattern), std::move(handler), retained});
  if (!connected_) return;  // handle_connack subscribes it
  send_subscribe(subscriptions_.back());
  watch();
}

void MqttClient::unsubscribe(const std::string& pattern) {
  const auto erased = std::erase_if(subscriptions_, [&](const Subscription& s) { return s.pattern == pattern; });
  if (erased == 0 || !connected_) return;
  mosquitto_unsubscribe(mosq_, nullptr, pattern.c_str());
  watch();
}

// `rc` is libmosquitto's error, or with MQTT 5 the reason code of the broker's DISCONNECT.
void MqttClient::handle_disconnect(int rc) {
  if (!connected_) return;
  connected_ = false;
  state_since_ = std::chrono::system_clock::now();
  ++counters_.drops;
  using mqtt::ConnectionEnd;
  const auto end = options_.version == 5 && rc == MQTT_RC_SESSION_TAKEN_OVER ? ConnectionEnd::taken_over
                   : rc == MOSQ_ERR_CONN_LOST                                ? ConnectionEnd::closed_by_broker
                                                                             : ConnectionEnd::failed;
  taken_over_ = takeover_.ended(end, std::chrono::steady_clock::now());
  if (!running_) return;
  drop_logged_ = true;
  if (taken_over_) {
    ++counters_.session_takeovers;
    last_takeover_ = std::chrono::system_clock::now();
    spdlog::error("mqtt: {}:{} gave the session of client id {} to another client ({}): two clients must not share "
                  "one mqtt.client_id; trying again in {} s",
                  options_.host, options_.port, options_.client_id,
                  end == ConnectionEnd::taken_over ? "MQTT 5 reason 0x8E, session taken over"
                                                   : "closed by the broker soon after connecting, twice in a row",
                  mqtt::SessionTakeover::retry_after.count());
    return;
  }
  spdlog::warn("mqtt: the connection to {}:{} dropped", options_.host, options_.port);
}

}  // namespace unima::io
