#include "io/unimabus/unimabus_service.hpp"

#include <spdlog/spdlog.h>

#include "banks/table_catalog.hpp"
#include "io/activity.hpp"
#include "io/listen_error.hpp"
#include "io/unimabus/feed_transport.hpp"
#include "io/unimabus/replay_transport.hpp"
#include "io/unimabus/sim_transport.hpp"
#include "status/activity.hpp"
#include "unimabus/bus_status.hpp"

namespace unima::io {

using banks::BankId;
using Clock = unimabus::TelegramIntake::Clock;

namespace {

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

UnimabusService::UnimabusService(Runtime& runtime)
    : runtime_(runtime),
      presence_timer_(runtime.io.get_executor(), [this] { return runtime_.banks->intake->next_expiry(); }, [this] {
        log(runtime_.banks->intake->expire(Clock::now()));
        presence_timer_.watch();
      }) {
  transport_ = make_transport(runtime.config());
  recorder_ = make_recorder(runtime.config());
  runtime.banks->intake->set_recording(recorder_.get());
  runtime.publisher.set_transport(transport_.get());
  runtime.publisher.watch(*runtime.banks->store);
}

UnimabusService::~UnimabusService() { runtime_.publisher.set_transport(nullptr); }

std::unique_ptr<unimabus::Transport> UnimabusService::make_transport(const config::Config& config) {
  auto handler = [this](const unimabus::Telegram& t) { return take(t); };
  if (config.unimabus.transport == config::TransportKind::feed) {
    try {
      return std::make_unique<FeedTransport>(runtime_.io, config.unimabus.listen_at, config.unimabus.max_clients, handler,
                                             [this] { return runtime_.publisher.snapshot(); });
    } catch (const boost::system::system_error& e) {
      throw std::runtime_error(listen_error(config.unimabus.listen_origin,
                                            fmt::format("unimabus.listen {}", config.unimabus.listen),
                                            config.unimabus.listen, e.code()));
    }
  }
  if (config.unimabus.transport == config::TransportKind::replay) {
    const auto& replay = config.unimabus.replay;
    return std::make_unique<ReplayTransport>(runtime_.io, replay.recording, replay.speed, replay.loop, handler);
  }
  std::vector<unimabus::SimDevice> devices;
  for (unsigned n = 1; n <= 4; ++n)
    if (const auto& device = config.devices[n - 1])  // each D_N on its own, even at a shared address
      devices.push_back({device->address, 0, device->table->length(), device->table});
  for (unsigned slot : config.unimabus.sim.io_modules)
    devices.push_back({config.unimabus.address, static_cast<std::uint8_t>(slot), banks::s_bank_length,
                       banks::io_module_table()});
  return std::make_unique<SimTransport>(runtime_.io, unimabus::SimGenerator(config.unimabus.sim.seed, std::move(devices)),
                                        config.unimabus.sim.period, handler);
}

std::unique_ptr<TelegramRecorder> UnimabusService::make_recorder(const config::Config& config) const {
  if (config.unimabus.record.file.empty()) return nullptr;
  return std::make_unique<TelegramRecorder>(config.unimabus.record, runtime_.started_at);
}

std::string UnimabusService::take(const unimabus::Telegram& telegram) {
  auto taken = runtime_.banks->intake->take(telegram, Clock::now());
  if (!taken.changes.empty()) {
    log(taken.changes);
    presence_timer_.watch();
  }
  return std::move(taken.error);
}

void UnimabusService::log(const std::vector<unimabus::TelegramIntake::PresenceChange>& changes) const {
  for (const auto& change : changes)
    spdlog::info("unimabus: {} {}", describe_bank(runtime_.config(), change.bank), change.online ? "on-line" : "off-line");
}

void UnimabusService::start() {
  started_ = true;
  const auto& config = runtime_.config();
  for (unsigned n = 1; n <= 4; ++n)
    if (config.devices[n - 1])
      spdlog::info("bridge: {} at 0x{:04X}, {} registers", describe_bank(config, banks::device_bank(n)),
                   config.bank_bases[index_of(banks::device_bank(n))], runtime_.banks->store->length(banks::device_bank(n)));
  if (transport_) transport_->start();
}

void UnimabusService::stop() {
  if (!started_) return;
  started_ = false;
  if (transport_) transport_->stop();
  presence_timer_.cancel();
}

void UnimabusService::stage(const Banks& next) {
  const auto& running = runtime_.config().unimabus;
  if (!same_transport(running, next.config.unimabus)) next_transport_ = make_transport(next.config);
  new_recorder_ = !same_record(running.record, next.config.unimabus.record);
  if (new_recorder_) next_recorder_ = make_recorder(next.config);
}

void UnimabusService::abandon() {
  next_transport_.reset();
  next_recorder_.reset();
  new_recorder_ = false;
}

void UnimabusService::commit(const Banks& previous) {
  auto& intake = *runtime_.banks->intake;
  log(intake.take_over(*previous.intake, Clock::now()));
  runtime_.publisher.watch(*runtime_.banks->store);
  presence_timer_.cancel();
  presence_timer_.watch();
  if (new_recorder_) recorder_ = std::move(next_recorder_);
  new_recorder_ = false;
  intake.set_recording(recorder_.get());
  if (next_transport_) {
    if (transport_) transport_->stop();
    transport_ = std::move(next_transport_);
    runtime_.publisher.set_transport(transport_.get());
    if (started_) transport_->start();
  }
}

void UnimabusService::describe(status::Document& status) const {
  const auto& config = runtime_.config();
  const auto& intake = *runtime_.banks->intake;
  const auto& store = *runtime_.banks->store;
  const auto& counts = intake.counts();
  unimabus::UnimabusStatus bus;
  bus.led = status::activity(age<Clock>(intake.last_telegram()), counts.received, unimabus_led_lit);
  bus.transport = config::transport_name(config.unimabus.transport);
  if (!config.unimabus.record.file.empty()) bus.recording = config.unimabus.record.file;
  bus.telegrams_ignored = counts.ignored;
  bus.telegrams_refused = counts.refused;
  if (transport_) bus.clients = transport_->clients();
  status.unimabus = std::move(bus);

  std::vector<unimabus::DeviceStatus> devices;
  for (unsigned n = 1; n <= 4; ++n) {
    const auto bank = banks::device_bank(n);
    auto& d = devices.emplace_back(unimabus::DeviceStatus{std::string(banks::bank_name(bank)), {}, {}, false, {}});
    if (const auto& device = config.devices[n - 1]) {
      d.type = device->table->id;
      d.address = device->address;
      d.online = store.online(bank);
      d.telegrams = counts.taken[banks::index_of(bank)];
    }
  }
  status.devices = std::move(devices);
  std::vector<unimabus::ModuleStatus> modules;
  for (unsigned n = 1; n <= 7; ++n) {
    const auto bank = banks::module_bank(n);
    modules.push_back({std::string(banks::bank_name(bank)), n, store.online(bank), counts.taken[banks::index_of(bank)]});
  }
  status.modules = std::move(modules);
}

}  // namespace unima::io
