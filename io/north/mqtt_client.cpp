#include "io/north/mqtt_client.hpp"

#include <mosquitto.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <mutex>

#include <spdlog/spdlog.h>

namespace unima::io {

namespace {

using namespace std::chrono_literals;

constexpr std::chrono::milliseconds max_backoff = 60s;

std::string reason(int rc) {
  if (rc == MOSQ_ERR_ERRNO) return std::strerror(errno);
  return mosquitto_strerror(rc);
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
  // Every message goes to the socket at once, so that a broker that does not keep up
  // shows as a socket that wants writing (backlogged()), not as a queue inside the library.
  mosquitto_max_inflight_messages_set(mosq, 0);
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
  mosquitto_message_callback_set(mosq, [](mosquitto*, void* self, const mosquitto_message* message) {
    auto& client = *static_cast<MqttClient*>(self);
    if (!client.on_message_ || message->topic == nullptr) return;
    client.on_message_(message->topic, std::string_view(static_cast<const char*>(message->payload),
                                                        static_cast<std::size_t>(std::max(message->payloadlen, 0))));
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
  misc_timer_.cancel();
  retry_timer_.cancel();
  resolver_.cancel();
  if (connected_) {
    if (!options_.status_topic.empty()) publish(options_.status_topic, "offline", true);
    mosquitto_disconnect(mosq_);  // written at once: the broker forgets the will
    connected_ = false;
    spdlog::info("mqtt: disconnected from {}:{}", options_.host, options_.port);
  }
  release_socket();
}

bool MqttClient::backlogged() const { return connected_ && mosquitto_want_write(mosq_); }

bool MqttClient::publish(const std::string& topic, std::string_view payload, bool retain) {
  if (!connected_) return false;
  const int rc = mosquitto_publish(mosq_, nullptr, topic.c_str(), static_cast<int>(payload.size()), payload.data(), 1, retain);
  if (rc != MOSQ_ERR_SUCCESS) return false;
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
  if (make_will_) {
    const auto will = make_will_();
    mosquitto_will_set(mosq_, will.topic.c_str(), static_cast<int>(will.payload.size()), will.payload.data(), will.qos, will.retain);
  }
  const int rc = mosquitto_connect_async(mosq_, host.c_str(), options_.port, static_cast<int>(options_.keepalive.count()));
  const int fd = mosquitto_socket(mosq_);
  if (rc != MOSQ_ERR_SUCCESS || fd < 0) return lost(reason(rc));
  socket_.emplace(io_, fd);
  watch();
}

void MqttClient::watch() {
  if (!socket_) return;
  if (!reading_) {
    reading_ = true;
    socket_->async_wait(asio::posix::stream_descriptor::wait_read, [this, alive = alive_](const boost::system::error_code& ec) {
      if (!*alive) return;
      reading_ = false;
      if (ec || !socket_) return;
      after_io(mosquitto_loop_read(mosq_, 1));
    });
  }
  if (!writing_ && mosquitto_want_write(mosq_)) {
    writing_ = true;
    socket_->async_wait(asio::posix::stream_descriptor::wait_write, [this, alive = alive_](const boost::system::error_code& ec) {
      if (!*alive) return;
      writing_ = false;
      if (ec || !socket_) return;
      after_io(mosquitto_loop_write(mosq_, 1));
    });
  }
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

void MqttClient::lost(const std::string& why) {
  release_socket();
  if (connected_) handle_disconnect(MOSQ_ERR_CONN_LOST);
  // Never inside one of libmosquitto's calls: lost() runs after they return.
  mosquitto_destroy(mosq_);
  mosq_ = make_handle();
  last_error_ = refusal_.empty() ? why : std::exchange(refusal_, {});
  if (!drop_logged_) {
    spdlog::warn("mqtt: no connection to {}:{}: {}; trying again with back-off", options_.host, options_.port, last_error_);
    drop_logged_ = true;
  }
  retry_later();
}

void MqttClient::retry_later() {
  if (!running_) return;
  std::uniform_real_distribution<double> spread(0.75, 1.25);
  const auto wait = std::chrono::milliseconds(static_cast<long>(backoff_.count() * spread(jitter_)));
  backoff_ = std::min(backoff_ * 2, max_backoff);
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
  connected_ = true;
  drop_logged_ = false;
  last_error_.clear();
  backoff_ = 1s;
  ++counters_.connections;
  connected_since_ = std::chrono::system_clock::now();
  spdlog::info("mqtt: connected to {}:{} as {}", options_.host, options_.port, options_.client_id);
  if (!options_.status_topic.empty()) publish(options_.status_topic, "online", true);
  if (!subscription_.empty()) mosquitto_subscribe(mosq_, nullptr, subscription_.c_str(), 1);
  for (const auto& pattern : more_subscriptions_) mosquitto_subscribe(mosq_, nullptr, pattern.c_str(), 1);
  if (on_connected_) on_connected_();
}

void MqttClient::handle_disconnect(int) {
  if (!connected_) return;
  connected_ = false;
  connected_since_.reset();
  ++counters_.drops;
  if (running_) {
    spdlog::warn("mqtt: the connection to {}:{} dropped", options_.host, options_.port);
    drop_logged_ = true;
  }
}

}  // namespace unima::io
