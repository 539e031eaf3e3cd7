#include "io/master/master_service.hpp"

#include <spdlog/spdlog.h>

#include "io/modbus/port_counters.hpp"
#include "modbus/request_handler.hpp"

namespace unima::io {

MasterService::MasterService(Runtime& runtime) : runtime_(runtime), master_(make_master(runtime.config())) {
  // To whichever master runs now: a reload swaps it.
  runtime_.forward_to_line = [this](GatewayRequest request, GatewayAnswer answer) {
    if (master_) return master_->forward(std::move(request), std::move(answer));
    asio::post(runtime_.io, [fn = request.pdu.at(0), answer = std::move(answer)] {
      std::array<std::uint8_t, 2> pdu{};
      modbus::write_exception(fn, modbus::ExceptionCode::gateway_target_failed, pdu);
      answer(pdu);
    });
  };
}

std::shared_ptr<MasterPort> MasterService::make_master(const config::Config& config) {
  if (config.modbus.mode != config::ModbusMode::master) return nullptr;
  MasterPort::Hooks hooks;
  hooks.read_source = [this](const banks::SourceRef& source) -> std::optional<std::uint16_t> {
    const auto value = runtime_.banks->store->read_source(source);
    if (!source.bit && value == banks::not_measured) return std::nullopt;
    return value;
  };
  hooks.set_output = [this](unsigned output, std::uint16_t value) { runtime_.banks->store->set_user_output(output, value); };
  hooks.on_fault = [this] { runtime_.error_hold.fault(); };
  hooks.on_transaction = [this](const modbus::Transaction& t) {
    runtime_.monitor->observe(t);
    if (spdlog::should_log(spdlog::level::debug)) spdlog::debug("modbus master: {}", describe_master_transaction(t));
  };
  hooks.on_query_sent = [this](std::chrono::system_clock::time_point time) { runtime_.monitor->frame_sent(time); };
  return MasterPort::create(runtime_.io, config, std::move(hooks));
}

void MasterService::start() {
  started_ = true;
  if (master_) master_->start();
}

void MasterService::stop() {
  started_ = false;
  if (master_) master_->stop();
}

void MasterService::stage(const Banks& next) { next_ = make_master(next.config); }

void MasterService::commit(const Banks&) {
  if (master_) master_->stop();
  master_ = std::move(next_);
  if (master_ && started_) master_->start();
}

void MasterService::describe(nlohmann::json& status) const {
  const auto& counters = runtime_.monitor->counters(modbus::PortKind::master);
  if (counters.transactions > 0) status["ports"].push_back(port_counters("master", counters));
  if (!master_) return;
  auto& devices = status["master"] = nlohmann::json::array();
  for (const auto& [device, c] : master_->counters())
    devices.push_back({{"device", device},     {"requests", c.requests},     {"answered", c.answered},
                       {"timeouts", c.timeouts}, {"exceptions", c.exceptions}, {"bad_frames", c.bad_frames},
                       {"retries", c.retries}});
}

}  // namespace unima::io
