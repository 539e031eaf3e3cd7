#include "app/bridge.hpp"

#include <unistd.h>

#include <spdlog/spdlog.h>

#include "io/master/master_service.hpp"
#include "io/modbus/rtu_slave_service.hpp"
#include "io/modbus/tcp_slave_service.hpp"
#include "io/monitor_service.hpp"
#include "io/http/http_service.hpp"
#include "io/mqtt/mqtt_service.hpp"
#include "io/mqtt/sparkplug_service.hpp"
#include "io/state_service.hpp"
#include "io/status_socket_service.hpp"
#include "io/unimabus/unimabus_service.hpp"
#include "platform/process_memory.hpp"
#include "status/document.hpp"

namespace unima::app {

Bridge::Bridge(asio::io_context& io, config::Config config)
    : runtime_(io, io::build_banks(std::move(config), nullptr)) {
  runtime_.status = [this] { return status(); };
  // The services, in the order they start. The state comes back before anything is
  // served or published; the ports' hooks point at the monitor.
  using Security = io::TcpSlaveService::Security;
  services_.push_back(std::make_unique<io::MonitorService>(runtime_));
  services_.push_back(std::make_unique<io::StateService>(runtime_));
  services_.push_back(std::make_unique<io::UnimabusService>(runtime_));
  services_.push_back(std::make_unique<io::TcpSlaveService>(runtime_, Security::plain));
  services_.push_back(std::make_unique<io::TcpSlaveService>(runtime_, Security::tls));
  services_.push_back(std::make_unique<io::RtuSlaveService>(runtime_));
  services_.push_back(std::make_unique<io::MasterService>(runtime_));
  services_.push_back(std::make_unique<io::StatusSocketService>(runtime_));
  services_.push_back(std::make_unique<io::HttpService>(runtime_));
  services_.push_back(std::make_unique<io::MqttService>(runtime_));
  services_.push_back(std::make_unique<io::SparkplugService>(runtime_));
}

Bridge::~Bridge() {
  stop();
  // The services go first: their ports and transports point into the runtime.
  while (!services_.empty()) services_.pop_back();
}

void Bridge::start() {
  started_ = true;
  const auto& config = runtime_.config();
  spdlog::info("bridge: UnimaBUS address {}, Modbus address {}, {} transport", config.unimabus.address,
               config.modbus.address, config::transport_name(config.unimabus.transport));
  for (const auto& warning : config::warnings(config)) spdlog::warn("{}", warning);
  for (auto& service : services_) service->start();
}

void Bridge::stop() {
  if (!started_) return;
  started_ = false;
  for (auto it = services_.rbegin(); it != services_.rend(); ++it) (*it)->stop();
  runtime_.error_hold.cancel();
}

void Bridge::reload(config::Config config) {
  auto next = io::build_banks(std::move(config), runtime_.state.get());
  // Everything that can fail comes first, while the running config serves on.
  std::size_t staged = 0;
  try {
    for (; staged < services_.size(); ++staged) services_[staged]->stage(*next);
  } catch (...) {
    for (std::size_t i = std::min(staged + 1, services_.size()); i-- > 0;) services_[i]->abandon();
    throw;
  }
  // Nothing below can fail: the values carry over, the banks swap, the services switch.
  next->store->take_state_from(*runtime_.banks->store);
  const auto previous = std::exchange(runtime_.banks, std::move(next));
  runtime_.changes.attach(*runtime_.banks->store);
  for (auto& service : services_) service->commit(*previous);
  for (const auto& warning : config::warnings(runtime_.config())) spdlog::warn("{}", warning);
  spdlog::info("bridge: reloaded {}", runtime_.config().file);
}

void Bridge::config_in_force_changed() {
  for (auto& service : services_) service->config_in_force_changed();
}

remote::ProbeFacts Bridge::probe_facts() const {
  remote::ProbeFacts facts;
  for (const auto& service : services_) service->probe(facts);
  return facts;
}

// What the seed's front panel and monitor LEDs show (seed 004 §8, SPEC §8) plus the
// counters: the bridge's own part here, each service's from it.
status::Document Bridge::status() const {
  const auto& config = runtime_.config();
  const auto online_bits = runtime_.banks->store->online_bits();
  status::Document doc;
  doc.bridge = status::BridgeStatus{
      ::getpid(),
      config.file,
      std::chrono::duration_cast<std::chrono::seconds>(std::chrono::steady_clock::now() - runtime_.started_at).count(),
      platform::resident_bytes(),
      config.modbus.mode == config::ModbusMode::master ? "master" : "slave",
      config.modbus.address,
      config.unimabus.address,
      (online_bits >> banks::c_bank::modbus_error_bit & 1) != 0,
      online_bits};
  for (const auto& service : services_) service->describe(doc);
  if (runtime_.config_changes) doc.config_in_force = runtime_.config_changes->status();
  return doc;
}

}  // namespace unima::app
