#include "io/runtime.hpp"

#include "banks/table_catalog.hpp"

namespace unima::io {

namespace {

std::vector<std::pair<banks::BankId, std::uint8_t>> device_addresses(const config::Config& config) {
  std::vector<std::pair<banks::BankId, std::uint8_t>> addresses;
  for (unsigned n = 1; n <= 4; ++n)
    if (const auto& device = config.devices[n - 1]) addresses.emplace_back(banks::device_bank(n), device->address);
  return addresses;
}

CaptureRules capture_rules(const config::Config& config) {
  CaptureRules rules;
  for (const auto* block : config.active_blocks())
    if (block->type == config::Block::Type::capture) rules[block->line].push_back({block->device, block->reg, block->output});
  return rules;
}

}  // namespace

std::unique_ptr<Banks> build_banks(config::Config config, banks::WriteJournal* journal) {
  auto b = std::make_unique<Banks>();
  b->store = std::make_unique<banks::RegisterStore>(config::bank_shapes(config));
  b->store->set_mapping(config.mapping);
  b->space = std::make_unique<banks::RegisterSpace>(config::address_map(config), *b->store,
                                                    banks::AccessRules{config.modbus.readable_write_banks});
  b->writes = std::make_unique<banks::WritePath>(*b->space, journal);
  b->writes->freeze(config::writes_frozen(config));
  b->intake = std::make_unique<unimabus::TelegramIntake>(
      unimabus::standard_routes(config.unimabus.address, *b->store, device_addresses(config)), *b->store,
      config.unimabus.offline_after);
  b->capture_rules = capture_rules(config);
  b->register_rows = config::register_map(config);
  b->value_model = values::ValueModel(config);
  b->values = std::make_unique<values::CurrentValues>(*b->store, b->value_model);
  // A deadband that names no value fails the start or the reload, at its key.
  b->deadbands = report::Deadbands(config.report, b->value_model);
  b->config = std::move(config);
  return b;
}

Runtime::Runtime(asio::io_context& io_context, std::unique_ptr<Banks> first)
    : io(io_context),
      banks(std::move(first)),
      monitor(std::make_unique<monitor::Monitor>(banks->config.monitor)),
      // The error hold outlives every port that reports a fault to it.
      error_hold(io_context, [this](bool error) { banks->store->set_modbus_error(error); }),
      changes(io_context) {
  changes.attach(*banks->store);
  if (!banks->config.state.file.empty()) {
    state = std::make_unique<StateFile>(io, banks->config.state.file);
    banks->writes->set_journal(state.get());
    // A durable write goes into the banks running when it is durable, which a reload may
    // have swapped since it was kept; a refused one is a fault (SPEC §1, C+0x13 bit 15).
    state->set_outcome({[this](std::span<const banks::WrittenValue> write) { banks->writes->commit(write); },
                        [this] { error_hold.fault(); }});
  }
}

}  // namespace unima::io
