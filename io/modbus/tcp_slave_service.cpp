#include "io/modbus/tcp_slave_service.hpp"

#include <spdlog/spdlog.h>

#include "io/modbus/slave_context.hpp"
#include "io/handshake_admission.hpp"
#include "io/listen_error.hpp"
#include "io/tls_context.hpp"
#include "status/port_status.hpp"

namespace unima::io {

namespace {

TcpSlaveOptions slave_options(const config::TcpSlaveConfig& c) {
  TcpSlaveOptions options;
  options.listen = c.listen;
  options.port = c.port;
  options.max_clients = c.max_clients;
  options.idle_timeout = c.idle_timeout;
  options.frame_timeout = c.frame_timeout;
  options.allow = c.allow;
  options.read_only = c.read_only;
  return options;
}

bool same_endpoint(const config::TcpSlaveConfig* a, const config::TcpSlaveConfig* b) {
  if ((a == nullptr) != (b == nullptr)) return false;
  return !a || (a->listen == b->listen && a->port == b->port);
}

}  // namespace

TcpSlaveService::TcpSlaveService(Runtime& runtime, Security security)
    : runtime_(runtime), security_(security), server_(make_server(runtime.config())) {}

const config::TcpSlaveConfig* TcpSlaveService::settings(const config::Config& config) const {
  if (security_ == Security::plain) return config.modbus.tcp ? &*config.modbus.tcp : nullptr;
  return config.modbus.tls ? &config.modbus.tls->connection : nullptr;
}

std::unique_ptr<TcpSlaveServer> TcpSlaveService::make_server(const config::Config& config) const {
  const auto* c = settings(config);
  if (!c) return nullptr;
  auto options = slave_options(*c);
  if (security_ == Security::tls) {
    const auto& tls = *config.modbus.tls;
    try {
      options.tls = TlsSlaveSetup{make_server_tls_context(modbus_tls_files(tls)), tls.roles, handshakes_, handshake_worker_};
    } catch (const std::exception& e) {
      throw std::runtime_error(fmt::format("{}: {}", tls.origin, e.what()));
    }
  }
  const auto* key = security_ == Security::tls ? "modbus.tls.port" : "modbus.tcp.port";
  try {
    return std::make_unique<TcpSlaveServer>(runtime_.io, options, slave_context(runtime_));
  } catch (const boost::system::system_error& e) {
    throw std::runtime_error(listen_error(c->port_origin, fmt::format("{} {}", key, c->port),
                                          listen_address(c->listen, c->port), e.code()));
  }
}

void TcpSlaveService::start() { server_.start(); }

void TcpSlaveService::stop() { server_.stop(); }

void TcpSlaveService::stage(const Banks& next) {
  if (!same_endpoint(settings(runtime_.config()), settings(next.config)))
    return server_.move([&] { return make_server(next.config); });
  // A renewal needs no restart; new files that do not load leave the running ones (SPEC §11).
  if (server_ && security_ == Security::tls) {
    try {
      next_context_ = make_server_tls_context(modbus_tls_files(*next.config.modbus.tls));
    } catch (const std::exception& e) {
      spdlog::error("modbus tls: {}; the running certificate keeps serving", e.what());
    }
  }
}

void TcpSlaveService::abandon() {
  next_context_.reset();
  server_.abandon([this](const TcpSlaveOptions& options) {
    return std::make_unique<TcpSlaveServer>(runtime_.io, options, slave_context(runtime_));
  });
}

void TcpSlaveService::commit(const Banks&) {
  server_.commit();
  if (!server_) return;
  const auto& c = *settings(runtime_.config());
  server_->set_limits(c.max_clients, c.idle_timeout, c.frame_timeout);
  server_->set_access(c.allow, c.read_only);
  if (security_ == Security::tls) {
    auto context = next_context_ ? std::move(next_context_) : server_->options().tls->context;
    server_->set_tls(TlsSlaveSetup{std::move(context), runtime_.config().modbus.tls->roles, handshakes_, handshake_worker_});
  }
  next_context_.reset();
  server_->set_context(slave_context(runtime_));
}

// A configured port is bound from its stage on (a bind that fails refuses the reload); the
// probe still asks, so that a listener that could not be kept is seen.
void TcpSlaveService::probe(remote::ProbeFacts& facts) const {
  const auto* c = settings(runtime_.config());
  if (!c) return;
  facts.listeners.emplace_back(fmt::format("modbus.{} {}:{}", security_ == Security::tls ? "tls" : "tcp", c->listen, c->port),
                               static_cast<bool>(server_));
}

// A port is listed while it is configured or has seen traffic.
void TcpSlaveService::describe(status::Document& status) const {
  const auto kind = security_ == Security::tls ? modbus::PortKind::tls : modbus::PortKind::tcp;
  const auto& counters = runtime_.monitor->counters(kind);
  if (!server_ && counters.transactions == 0) return;
  auto port = status::port_status(security_ == Security::tls ? "tls" : "tcp", counters);
  if (server_) {
    port.listen = server_->options().listen + ":" + std::to_string(server_->port());
    port.clients = server_->client_count();
  }
  if (security_ == Security::tls) port.handshakes = handshake_counters(*handshakes_);
  status.ports.push_back(std::move(port));
}

}  // namespace unima::io
