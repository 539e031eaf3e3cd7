#include "io/state_service.hpp"

#include <spdlog/spdlog.h>

#include "state/state_status.hpp"

namespace unima::io {

// The first feed snapshot must carry what the file brought back, so it goes into the
// store before any service starts. A write block's output comes back only where this
// config still has a write block for it.
StateService::StateService(Runtime& runtime) : runtime_(runtime) {
  if (!runtime.state) return;
  const auto& image = runtime.state->restored();
  auto& store = *runtime.banks->store;
  for (std::uint16_t i = 0; i < store.length(banks::BankId::W); ++i)
    if (const auto value = image.w(i)) store.write(banks::BankId::W, i, *value);
  if (const auto value = image.x(); value && store.exists(banks::BankId::X)) store.write(banks::BankId::X, 0, *value);
  for (const auto* block : runtime.config().active_blocks())
    if (block->type == config::Block::Type::write)
      if (const auto value = image.output(block->output)) store.set_user_output(block->output, *value);
}

void StateService::stage(const Banks& next) {
  const auto& running = runtime_.config().state.file;
  if (running != next.config.state.file)
    spdlog::warn("{}: state.file changes at the next start; until then the state stays in {}", next.config.file,
                 running.empty() ? "no file" : running);
}

void StateService::describe(status::Document& status) const {
  state::StateStatus state;
  if (const auto& file = runtime_.state) {
    const auto counters = file->counters();
    state = {file->path().string(), counters.records, counters.syncs, counters.failures};
  }
  status.state = std::move(state);
}

}  // namespace unima::io
