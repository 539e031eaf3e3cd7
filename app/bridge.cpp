#include "app/bridge.hpp"

#include <spdlog/spdlog.h>

#include "app/bridge_core.hpp"
#include "app/reload_plan.hpp"
#include "banks/register_space.hpp"
#include "banks/table_catalog.hpp"
#include "config/socket_path.hpp"
#include "io/unimabus/feed_transport.hpp"
#include "io/unimabus/replay_transport.hpp"
#include "io/unimabus/sim_transport.hpp"
#include "io/tls_context.hpp"
#include "modbus/capture.hpp"

namespace unima::app {

using banks::BankId;

namespace {

std::vector<std::pair<BankId, std::uint8_t>> device_addresses(const config::Config& config) {
  std::vector<std::pair<BankId, std::uint8_t>> addresses;
  for (unsigned n = 1; n <= 4; ++n)
    if (const auto& device = config.devices[n - 1]) addresses.emplace_back(banks::device_bank(n), device->address);
  return addresses;
}

std::vector<modbus::CaptureRule> capture_rules(const config::Config& config) {
  std::vector<modbus::CaptureRule> rules;
  for (const auto* block : config.active_blocks())
    if (block->type == config::Block::Type::capture) rules.push_back({block->device, block->reg, block->output});
  return rules;
}

// In master mode the line belongs to the master (SPEC §3).
std::optional<config::RtuConfig> slave_line(const config::Config& config) {
  if (config.modbus.mode != config::ModbusMode::slave) return std::nullopt;
  return config.modbus.rtu;
}

std::string describe_bank(const config::Config& config, BankId bank) {
  if (banks::is_device_bank(bank)) {
    const auto& device = config.devices[banks::bank_number(bank) - 1];
    if (device) return fmt::format("{} ({} at UnimaBUS address {})", banks::bank_name(bank), device->table->id, device->address);
  }
  if (banks::is_module_bank(bank))
    return fmt::format("{} (IO module in slot {} at address {})", banks::bank_name(bank), banks::bank_number(bank),
                       config.unimabus.address);
  return std::string(banks::bank_name(bank));
}

}  // namespace

Bridge::Bridge(asio::io_context& io, config::Config config)
    : io_(io),
      core_(build_core(std::move(config))),
      error_hold_(io, [this](bool error) { core_->store->set_modbus_error(error); }),
      presence_timer_(io.get_executor(), [this] { return core_->intake->next_expiry(); },
                      [this] { expire_presence(); }),
      mqtt_timer_(io), heartbeat_timer_(io) {
  monitor_ = std::make_unique<monitor::Monitor>(core_->config.monitor);
  if (!core_->config.state.file.empty()) {
    state_ = std::make_unique<io::StateFile>(io_, core_->config.state.file);
    core_->writes->set_journal(state_.get());
    restore_state();
  }
  transport_ = make_transport(core_->config);
  recorder_ = make_recorder(core_->config);
  core_->intake->set_recording(recorder_.get());
  tcp_ = make_tcp_server(core_->config);
  tls_ = make_tls_server(core_->config);
  rtu_ = make_rtu_port(core_->config);
  master_ = make_master(core_->config);
  control_ = make_control_socket(core_->config.status.socket);
  http_users_ = read_http_users(core_->config, nullptr);
  http_ = make_http_server(core_->config);
  mqtt_ = make_mqtt(core_->config);
  lay_out();
  publisher_.set_transport(transport_.get());
  publisher_.watch(*core_->store);
}

Bridge::~Bridge() { stop(); }

const config::Config& Bridge::config() const { return core_->config; }

std::unique_ptr<Bridge::Core> Bridge::build_core(config::Config config) {
  auto core = std::make_unique<Core>();
  core->store = std::make_unique<banks::RegisterStore>(config::bank_shapes(config));
  core->store->set_mapping(config.mapping);
  core->space = std::make_unique<banks::RegisterSpace>(config::address_map(config), *core->store,
                                                       banks::AccessRules{config.modbus.readable_write_banks});
  core->writes = std::make_unique<banks::WritePath>(*core->space, state_.get());
  core->intake = std::make_unique<unimabus::TelegramIntake>(
      unimabus::standard_routes(config.unimabus.address, *core->store, device_addresses(config)), *core->store,
      config.unimabus.offline_after);
  core->capture_rules = capture_rules(config);
  core->config = std::move(config);
  return core;
}

std::unique_ptr<unimabus::Transport> Bridge::make_transport(const config::Config& config) {
  auto handler = [this](const unimabus::Telegram& t) { return on_telegram(t); };
  if (config.unimabus.transport == config::TransportKind::feed) {
    try {
      return std::make_unique<io::FeedTransport>(io_, config.unimabus.listen_at, config.unimabus.max_clients, handler,
                                                 [this] { return publisher_.snapshot(); });
    } catch (const boost::system::system_error& e) {
      throw std::runtime_error(
          fmt::format("unimabus.listen: cannot listen on {}: {}", config.unimabus.listen, e.code().message()));
    }
  }
  if (config.unimabus.transport == config::TransportKind::replay) {
    const auto& replay = config.unimabus.replay;
    return std::make_unique<io::ReplayTransport>(io_, replay.recording, replay.speed, replay.loop, handler);
  }
  std::vector<unimabus::SimDevice> devices;
  for (unsigned n = 1; n <= 4; ++n)
    if (const auto& device = config.devices[n - 1])  // each D_N on its own, even at a shared address
      devices.push_back({device->address, 0, device->table->length(), device->table});
  for (unsigned slot : config.unimabus.sim.io_modules)
    devices.push_back({config.unimabus.address, static_cast<std::uint8_t>(slot), banks::s_bank_length,
                       banks::io_module_table()});
  return std::make_unique<io::SimTransport>(io_, unimabus::SimGenerator(config.unimabus.sim.seed, std::move(devices)),
                                        config.unimabus.sim.period, handler);
}

namespace {

io::TcpSlaveOptions slave_options(const config::TcpSlaveConfig& c) {
  io::TcpSlaveOptions options;
  options.listen = c.listen;
  options.port = c.port;
  options.max_clients = c.max_clients;
  options.idle_timeout = c.idle_timeout;
  options.frame_timeout = c.frame_timeout;
  options.allow = c.allow;
  options.read_only = c.read_only;
  return options;
}

tls::TlsFiles tls_files(const config::TlsSlaveConfig& tls) { return {tls.certificate, tls.key, tls.ca}; }

}  // namespace

std::unique_ptr<io::TcpSlaveServer> Bridge::make_tcp_server(const config::Config& config) {
  if (!config.modbus.tcp) return nullptr;
  const auto& tcp = *config.modbus.tcp;
  const auto options = slave_options(tcp);
  try {
    return std::make_unique<io::TcpSlaveServer>(io_, options, slave_context());
  } catch (const boost::system::system_error& e) {
    throw std::runtime_error(fmt::format("modbus tcp: cannot listen on {}:{}: {}", tcp.listen, tcp.port, e.code().message()));
  }
}

// SPEC §11: the same slave over TLS, on its own listener beside (or instead of) plain TCP.
std::unique_ptr<io::TcpSlaveServer> Bridge::make_tls_server(const config::Config& config) {
  if (!config.modbus.tls) return nullptr;
  const auto& tls = *config.modbus.tls;
  const auto& c = tls.connection;
  auto options = slave_options(c);
  try {
    options.tls = io::TlsSlaveSetup{io::make_server_tls_context(tls_files(tls)), tls.roles};
  } catch (const std::exception& e) {
    throw std::runtime_error(fmt::format("{}: {}", tls.origin, e.what()));
  }
  try {
    return std::make_unique<io::TcpSlaveServer>(io_, options, slave_context());
  } catch (const boost::system::system_error& e) {
    throw std::runtime_error(fmt::format("modbus tls: cannot listen on {}:{}: {}", c.listen, c.port, e.code().message()));
  }
}

// On reload the certificate and key are read again (a renewal needs no restart); a new
// one that does not load leaves the running one serving (SPEC §11).
std::shared_ptr<asio::ssl::context> Bridge::renewed_tls_context(const config::TlsSlaveConfig& tls) const {
  try {
    return io::make_server_tls_context(tls_files(tls));
  } catch (const std::exception& e) {
    spdlog::error("modbus tls: {}; the running certificate keeps serving", e.what());
    return nullptr;
  }
}

std::unique_ptr<io::RtuSlavePort> Bridge::make_rtu_port(const config::Config& config) {
  const auto line = slave_line(config);
  if (!line) return nullptr;
  auto port = std::make_unique<io::RtuSlavePort>(io_, *line, rtu_context());
  port->set_foreign_listener([this](std::span<const std::uint8_t> query, std::span<const std::uint8_t> response) {
    on_foreign_exchange(query, response);
  });
  return port;
}

io::SlaveContext Bridge::rtu_context() {
  auto context = slave_context();
  context.options.max_read_registers = modbus::max_read_registers_rtu;
  return context;
}

// Capture blocks (SPEC §4): a write is taken from the master's request, a read from the
// foreign slave's response.
void Bridge::on_foreign_exchange(std::span<const std::uint8_t> query, std::span<const std::uint8_t> response) {
  const auto& rules = core_->capture_rules;
  if (rules.empty()) return;
  const auto captured = response.empty() ? modbus::captured_writes(rules, query)
                                         : modbus::captured_reads(rules, query, response);
  for (const auto& c : captured) {
    core_->store->set_user_output(c.output, c.value);
    spdlog::debug("capture: user output {} = {} ({} of device {})", c.output, c.value,
                  c.via == modbus::Captured::Via::write ? "write" : "read", query[0]);
  }
}

// In master mode the RTU line is the master's (SPEC §3); the TCP slave keeps serving.
std::shared_ptr<io::MasterPort> Bridge::make_master(const config::Config& config) {
  if (config.modbus.mode != config::ModbusMode::master) return nullptr;
  io::MasterPort::Hooks hooks;
  // The hooks read the running core at each call, so they follow a reload.
  hooks.read_source = [this](const banks::SourceRef& source) -> std::optional<std::uint16_t> {
    const auto value = core_->store->read_source(source);
    if (!source.bit && value == banks::not_measured) return std::nullopt;
    return value;
  };
  hooks.set_output = [this](unsigned output, std::uint16_t value) { core_->store->set_user_output(output, value); };
  hooks.on_fault = [this] { error_hold_.fault(); };
  hooks.on_transaction = [this](const modbus::Transaction& t) {
    monitor_->observe(t);
    if (spdlog::should_log(spdlog::level::debug)) spdlog::debug("modbus master: {}", io::describe_master_transaction(t));
  };
  return io::MasterPort::create(io_, config, std::move(hooks));
}

// What the state file brought back goes into the store before anything is served or
// published, so the first feed snapshot carries it (SPEC §10). A write block's output comes
// back only where this config still has a write block for it.
void Bridge::restore_state() {
  const auto& image = state_->restored();
  auto& store = *core_->store;
  for (std::uint16_t i = 0; i < store.length(BankId::W); ++i)
    if (const auto value = image.w(i)) store.write(BankId::W, i, *value);
  if (const auto value = image.x(); value && store.exists(BankId::X)) store.write(BankId::X, 0, *value);
  for (const auto* block : core_->config.active_blocks())
    if (block->type == config::Block::Type::write)
      if (const auto value = image.output(block->output)) store.set_user_output(block->output, *value);
}

io::SlaveContext Bridge::slave_context() {
  io::SlaveContext context;
  context.registers = core_->writes.get();
  context.state = state_.get();
  context.unit_id = core_->config.modbus.address;
  const auto& ext = core_->config.modbus.extensions;
  context.options.max_read_registers = modbus::max_read_registers_tcp;
  context.options.read_holding_registers = ext.function_3;
  context.options.write_multiple_registers = ext.function_16;
  context.options.device_identification = ext.function_43;
  // The error hold lives as long as the bridge, and the ports never outlive the bridge.
  context.on_fault = [this] { error_hold_.fault(); };
  context.on_transaction = [monitor = monitor_.get()](const modbus::Transaction& t) { monitor->observe(t); };
  return context;
}

void Bridge::start() {
  started_ = true;
  spdlog::info("bridge: UnimaBUS address {}, Modbus address {}, {} transport", core_->config.unimabus.address,
               core_->config.modbus.address,
               config::transport_name(core_->config.unimabus.transport));
  for (const auto& warning : config::warnings(core_->config)) spdlog::warn("{}", warning);
  for (unsigned n = 1; n <= 4; ++n)
    if (core_->config.devices[n - 1])
      spdlog::info("bridge: {} at 0x{:04X}, {} registers", describe_bank(core_->config, banks::device_bank(n)),
                   core_->config.bank_bases[index_of(banks::device_bank(n))], core_->store->length(banks::device_bank(n)));
  if (transport_) transport_->start();
  if (tcp_) tcp_->start();
  if (tls_) tls_->start();
  if (rtu_) rtu_->start();
  if (master_) master_->start();
  if (control_) control_->start();
  if (http_) http_->start();
  if (mqtt_) {
    mqtt_->start();
    mqtt_tick();
  }
  heartbeat();
}

void Bridge::lay_out() {
  register_rows_ = config::register_map(core_->config);
  value_model_ = values::ValueModel(core_->config);
  lay_out_mqtt();
}

void Bridge::heartbeat() {
  const auto now = std::chrono::steady_clock::now();
  // A beat that comes over 2 s late is a stall that just ended: /healthz says so for a
  // while, so that a scraper polling every few seconds sees it.
  if (const auto gap = now - last_turn_; gap > stall_limit) {
    last_stall_ = std::chrono::duration_cast<std::chrono::milliseconds>(gap);
    stall_reported_until_ = now + stall_report_window;
  }
  last_turn_ = now;
  if (live_.listened()) live_.update(live_snapshot(), monitor_->recent());
  heartbeat_timer_.expires_after(std::chrono::milliseconds(250));
  heartbeat_timer_.async_wait([this](const boost::system::error_code& ec) {
    if (!ec && started_) heartbeat();
  });
}

std::unique_ptr<io::HttpServer> Bridge::make_http_server(const config::Config& config) {
  if (!config.http) return nullptr;
  io::HttpOptions options;
  options.listen = config.http->listen;
  options.port = config.http->port;
  options.max_clients = config.http->max_clients;
  if (const auto& tls = config.http->tls) options.tls = io::make_server_tls_context({tls->certificate, tls->key, {}}, "http.tls");
  return serve_http(options);
}

std::unique_ptr<io::HttpServer> Bridge::serve_http(const io::HttpOptions& options) {
  try {
    auto server = std::make_unique<io::HttpServer>(io_, options, [this](std::string_view target) { return http_response(target); });
    server->set_gate([this](std::string_view authorization, const std::string& peer) { return http_gate(authorization, peer); });
    return server;
  } catch (const boost::system::system_error& e) {
    throw std::runtime_error(fmt::format("http: cannot listen on {}:{}: {}", options.listen, options.port, e.code().message()));
  }
}

std::optional<web::BasicAuth> Bridge::read_http_users(const config::Config& config, const config::Config* running) const {
  if (!config.http || config.http->users.empty()) return std::nullopt;
  try {
    return web::BasicAuth::load(config.http->users);
  } catch (const std::exception& e) {
    if (running && running->http && running->http->users == config.http->users && http_users_) {
      spdlog::error("{}; the users read before stay", e.what());
      return http_users_;
    }
    throw;
  }
}

// The status socket is the operator's window, not part of the bridge's service: when it
// cannot listen (no /run/unima-bridge outside systemd, say) the bridge serves on. A path
// that names something else than a socket is refused like a bad config (SPEC §10).
std::unique_ptr<io::ControlSocket> Bridge::make_control_socket(const std::string& path) {
  try {
    return std::make_unique<io::ControlSocket>(io_, path, [this] { return status_document(); });
  } catch (const config::PathRefused&) {
    throw;
  } catch (const std::exception& e) {
    spdlog::warn("{}; `unima-bridge status` will not answer", e.what());
    return nullptr;
  }
}

void Bridge::stop() {
  if (!started_) return;
  started_ = false;
  if (rtu_) rtu_->stop();
  if (master_) master_->stop();
  if (tcp_) tcp_->stop();
  if (tls_) tls_->stop();
  if (transport_) transport_->stop();
  if (control_) control_->stop();
  if (http_) http_->stop();
  if (mqtt_) mqtt_->stop();
  mqtt_timer_.cancel();
  heartbeat_timer_.cancel();
  presence_timer_.cancel();
  error_hold_.cancel();
}

namespace {
bool same_endpoint(const std::optional<config::TcpSlaveConfig>& a, const std::optional<config::TcpSlaveConfig>& b) {
  if (a.has_value() != b.has_value()) return false;
  return !a || (a->listen == b->listen && a->port == b->port);
}
bool same_line(const std::optional<config::RtuConfig>& a, const std::optional<config::RtuConfig>& b) {
  if (a.has_value() != b.has_value()) return false;
  return !a || (a->device == b->device && a->baud == b->baud && a->parity == b->parity &&
                a->stop_bits == b->stop_bits && a->rs485 == b->rs485 && a->low_latency == b->low_latency &&
                a->frame_gap == b->frame_gap);
}
// A feed keeps its connections across a reload, and a replay its place, when their
// settings did not change; the simulator starts again.
bool same_transport(const config::UnimabusConfig& a, const config::UnimabusConfig& b) {
  if (a.transport != b.transport) return false;
  if (a.transport == config::TransportKind::feed) return a.listen == b.listen && a.max_clients == b.max_clients;
  if (a.transport == config::TransportKind::replay)
    return a.replay.file == b.replay.file && a.replay.loop == b.replay.loop && a.replay.speed == b.replay.speed &&
           *a.replay.recording == *b.replay.recording;
  return false;
}
bool same_record(const config::RecordConfig& a, const config::RecordConfig& b) {
  return a.file == b.file && a.max_size == b.max_size && a.max_files == b.max_files;
}
}  // namespace

void Bridge::reload(config::Config config) { commit(plan_reload(std::move(config))); }

// Everything that can fail comes first, while the running ports are untouched.
Bridge::ReloadPlan Bridge::plan_reload(config::Config config) {
  ReloadPlan plan;
  plan.core = build_core(std::move(config));
  const auto& old_config = core_->config;
  const auto& new_config = plan.core->config;
  if (old_config.state.file != new_config.state.file)
    spdlog::warn("{}: state.file changes at the next start; until then the state stays in {}", new_config.file,
                 old_config.state.file.empty() ? "no file" : old_config.state.file);
  if (!monitor::Monitor::same_log(old_config.monitor, new_config.monitor))
    plan.monitor_writer = monitor::Monitor::make_writer(new_config.monitor);
  // A status socket that could not listen before gets another chance.
  if (old_config.status.socket != new_config.status.socket || !control_)
    plan.control = make_control_socket(new_config.status.socket);
  if (!same_transport(old_config.unimabus, new_config.unimabus)) plan.transport = make_transport(new_config);
  plan.same_recorder = same_record(old_config.unimabus.record, new_config.unimabus.record);
  if (!plan.same_recorder) plan.recorder = make_recorder(new_config);
  plan.same_tcp = same_endpoint(old_config.modbus.tcp, new_config.modbus.tcp);
  plan.same_rtu = same_line(slave_line(old_config), slave_line(new_config));
  if (!plan.same_tcp && tcp_) {
    // The new server may want the same port on another address: the old one lets go
    // until the plan commits or is dropped.
    tcp_->stop();
    plan.restore_tcp = Rollback([this] {
      tcp_ = std::make_unique<io::TcpSlaveServer>(io_, tcp_->options(), slave_context());
      tcp_->start();
    });
  }
  if (!plan.same_tcp) plan.tcp = make_tcp_server(new_config);
  const auto tls_connection = [](const config::Config& c) {
    return c.modbus.tls ? std::optional(c.modbus.tls->connection) : std::nullopt;
  };
  plan.same_tls = same_endpoint(tls_connection(old_config), tls_connection(new_config));
  if (!plan.same_tls && tls_) {
    tls_->stop();
    plan.restore_tls = Rollback([this] {
      tls_ = std::make_unique<io::TcpSlaveServer>(io_, tls_->options(), slave_context());
      tls_->start();
    });
  }
  if (!plan.same_tls) plan.tls = make_tls_server(new_config);
  if (plan.same_tls && tls_) plan.tls_context = renewed_tls_context(*new_config.modbus.tls);
  plan.http_users = read_http_users(new_config, &old_config);
  const auto http_endpoint = [](const config::Config& c) {
    return c.http ? std::optional(std::tuple(c.http->listen, c.http->port, c.http->tls.has_value())) : std::nullopt;
  };
  plan.same_http = http_endpoint(old_config) == http_endpoint(new_config);
  if (!plan.same_http && http_) {
    http_->stop();
    plan.restore_http = Rollback([this, options = http_->options()] {
      http_ = serve_http(options);
      http_->start();
    });
  }
  if (!plan.same_http) {
    plan.http = make_http_server(new_config);
  } else if (http_ && new_config.http->tls) {
    // As for Modbus/TCP Security: renewed files are read, bad ones leave the running ones.
    try {
      const auto& tls = *new_config.http->tls;
      plan.http_tls_context = io::make_server_tls_context({tls.certificate, tls.key, {}}, "http.tls");
    } catch (const std::exception& e) {
      spdlog::error("http: {}; the running certificate keeps serving", e.what());
    }
  }
  plan.same_mqtt = old_config.mqtt.has_value() == new_config.mqtt.has_value() &&
                   (!old_config.mqtt || old_config.mqtt->same_client(*new_config.mqtt));
  if (!plan.same_mqtt) plan.mqtt = make_mqtt(new_config);
  // The master's line opens before anything is switched (a serial device may be missing).
  plan.master = make_master(new_config);
  return plan;
}

// Nothing here can fail: values and presence carried over, then the ports switched.
void Bridge::commit(ReloadPlan plan) {
  plan.restore_tcp.commit();
  plan.restore_tls.commit();
  plan.restore_http.commit();
  auto& core = plan.core;
  core->store->take_state_from(*core_->store);
  const auto presence = core->intake->take_over(*core_->intake, unimabus::TelegramIntake::Clock::now());
  core_ = std::move(core);
  monitor_->reconfigure(core_->config.monitor, std::move(plan.monitor_writer));
  if (plan.control) {  // else the running one stays, on a path that did not change or could not be taken
    if (control_) control_->stop();
    control_ = std::move(plan.control);
    control_->start();
  }
  publisher_.watch(*core_->store);
  presence_timer_.cancel();
  presence_timer_.watch();

  if (!plan.same_recorder) recorder_ = std::move(plan.recorder);
  core_->intake->set_recording(recorder_.get());
  log_presence(presence);
  if (plan.transport) {
    if (transport_) transport_->stop();
    transport_ = std::move(plan.transport);
    publisher_.set_transport(transport_.get());
    transport_->start();
  }
  if (!plan.same_tcp) {
    tcp_ = std::move(plan.tcp);
    if (tcp_) tcp_->start();
  }
  if (tcp_) {
    const auto& tcp = *core_->config.modbus.tcp;
    tcp_->set_limits(tcp.max_clients, tcp.idle_timeout, tcp.frame_timeout);
    tcp_->set_access(tcp.allow, tcp.read_only);
    tcp_->set_context(slave_context());
  }
  if (!plan.same_tls) {
    tls_ = std::move(plan.tls);
    if (tls_) tls_->start();
  }
  http_users_ = std::move(plan.http_users);
  if (!plan.same_http) {
    http_ = std::move(plan.http);
    if (http_) http_->start();
  } else if (http_ && plan.http_tls_context) {
    http_->set_tls_context(std::move(plan.http_tls_context));
  }
  if (tls_) {
    const auto& tls = *core_->config.modbus.tls;
    tls_->set_limits(tls.connection.max_clients, tls.connection.idle_timeout, tls.connection.frame_timeout);
    tls_->set_access(tls.connection.allow, tls.connection.read_only);
    auto context = plan.tls_context ? plan.tls_context : tls_->options().tls->context;
    tls_->set_tls(io::TlsSlaveSetup{std::move(context), tls.roles});
    tls_->set_context(slave_context());
  }
  if (!plan.same_mqtt) {
    if (mqtt_) mqtt_->stop();  // `offline`, a clean goodbye, before the new client says `online`
    mqtt_ = std::move(plan.mqtt);
    if (mqtt_) {
      mqtt_->start();
      mqtt_tick();
    }
  }
  lay_out();
  // The serial line is reopened only when its settings changed; opening never throws (a
  // line that cannot be opened is retried), so this comes after the commit.
  if (!plan.same_rtu) {
    if (rtu_) rtu_->stop();
    rtu_ = make_rtu_port(core_->config);
    if (rtu_) rtu_->start();
  } else if (rtu_) {
    rtu_->set_context(rtu_context());
  }
  if (master_) master_->stop();
  master_ = std::move(plan.master);
  if (master_) master_->start();
  for (const auto& warning : config::warnings(core_->config)) spdlog::warn("{}", warning);
  spdlog::info("bridge: reloaded {}", core_->config.file);
}

std::string Bridge::on_telegram(const unimabus::Telegram& telegram) {
  auto taken = core_->intake->take(telegram, unimabus::TelegramIntake::Clock::now());
  if (!taken.changes.empty()) {
    log_presence(taken.changes);
    presence_timer_.watch();
  }
  return std::move(taken.error);
}

std::unique_ptr<io::TelegramRecorder> Bridge::make_recorder(const config::Config& config) const {
  if (config.unimabus.record.file.empty()) return nullptr;
  return std::make_unique<io::TelegramRecorder>(config.unimabus.record, started_at_);
}

void Bridge::log_presence(const std::vector<unimabus::TelegramIntake::PresenceChange>& changes) const {
  for (const auto& change : changes)
    spdlog::info("unimabus: {} {}", describe_bank(core_->config, change.bank), change.online ? "on-line" : "off-line");
}

// One timer for all devices, at the earliest moment one can go off-line; telegrams only
// push that moment later (LazyDeadline).
void Bridge::expire_presence() {
  log_presence(core_->intake->expire(unimabus::TelegramIntake::Clock::now()));
  presence_timer_.watch();
}

}  // namespace unima::app
