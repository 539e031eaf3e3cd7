#include "app/remote_config_coordinator.hpp"

#include <memory>

#include <spdlog/spdlog.h>

#include "check/check_config.hpp"
#include "io/tls_context.hpp"
#include "platform/logging.hpp"
#include "platform/utc_time.hpp"
#include "remote/yaml_budget.hpp"

namespace unima::app {

namespace {

std::string now_utc() { return platform::utc_time_text(std::chrono::system_clock::now()); }

// The lock-out rule: a config may come by a channel only if it leaves that channel on.
std::optional<std::string> locks_out(const config::Config& next, remote::Source source, const std::string& by) {
  const auto& remote = next.remote_config;
  switch (source) {
    case remote::Source::cli:
      return std::nullopt;  // the control socket is always there for root and the daemon's user
    case remote::Source::mqtt:
      if (!next.mqtt || !remote || !remote->mqtt)
        return "it turns off remote_config.mqtt, the channel it came by: the fleet could not reach this bridge again";
      return std::nullopt;
    case remote::Source::http:
      if (!next.http || !remote || std::find(remote->http.begin(), remote->http.end(), by) == remote->http.end())
        return "it takes " + by + " out of remote_config.http, the channel it came by: the fleet could not reach this bridge again";
      return std::nullopt;
  }
  return std::nullopt;
}

std::chrono::milliseconds probe_of(const config::Config& config) {
  return config.remote_config ? config.remote_config->probe : config::RemoteConfig{}.probe;
}

}  // namespace

RemoteConfigCoordinator::RemoteConfigCoordinator(asio::io_context& io, Bridge& bridge, ConfigInForce& in_force)
    : bridge_(bridge), in_force_(in_force), probe_timer_(io),
      // A client waits for the answer: beside the loop, not behind every other program.
      worker_(io, 1, io::CpuWorker::Priority::beside_the_loop) {
  if (!in_force_.store_directory.empty()) {
    const auto& remote = in_force_.config.remote_config;
    store_.emplace(in_force_.store_directory, remote ? remote->keep : io::RemoteConfigStore::default_keep);
  }
  reloaded();
  bridge_.take_config_changes(this);
}

RemoteConfigCoordinator::~RemoteConfigCoordinator() { bridge_.take_config_changes(nullptr); }

void RemoteConfigCoordinator::apply(std::string text, remote::Source source, std::string by, Done done) {
  const auto id = remote::change_id(text);
  if (auto busy = flow_.begin({id, source, by})) {
    spdlog::warn("remote config: {} by {} refused: {}", remote::source_name(source), by, busy->reason);
    ++status_.changes_busy;
    return done(*busy);
  }
  change_ = Change{std::move(done), std::nullopt, std::move(text), source, std::move(by)};
  spdlog::info("remote config: {} by {}: {} bytes (sha256 {})", remote::source_name(source), change_->by,
               change_->text->size(), id);
  if (auto over = remote::over_budget(*change_->text)) return finish(flow_.refuse(*over));
  const auto origin = fmt::format("config from {} by {}", remote::source_name(source), change_->by);
  // As if it stood in the operator's file: what goes "beside the config" goes beside that.
  auto load = [text = *change_->text, origin, operator_file = in_force_.operator_file] {
    return config::load_text(text, origin, config::Host::this_machine(), operator_file);
  };
  load_then_apply(std::move(load), origin, "the config has errors");
}

void RemoteConfigCoordinator::revert(remote::Source source, std::string by, Done done) {
  std::string text;
  try {
    text = config::read_config_file(in_force_.operator_file);
  } catch (const std::exception& e) {
    spdlog::warn("remote config: {} by {}: {}", remote::source_name(source), by, e.what());
  }
  if (auto busy = flow_.begin({remote::change_id(text), source, by})) {
    ++status_.changes_busy;
    return done(*busy);
  }
  change_ = Change{std::move(done), std::nullopt, std::nullopt, source, std::move(by)};
  spdlog::info("remote config: {} by {}: back to the operator's file {}", remote::source_name(source), change_->by,
               in_force_.operator_file);
  load_then_apply([text = std::move(text), file = in_force_.operator_file] { return config::load_text(text, file); },
                  in_force_.operator_file, "the operator's file has errors");
}

// The load and check of a config took some 5 ms of the loop with TLS credentials (OpenSSL
// reads them for the host check and again for check_config's context;
// bench/remote_config.py), and more with many device tables: every Modbus client waited.
// They touch nothing of the running bridge, so they run on the worker.
void RemoteConfigCoordinator::load_then_apply(std::function<config::Config()> load, std::string origin, std::string refusal) {
  struct Loaded {
    std::optional<config::Config> config;
    std::string error;
  };
  auto loaded = std::make_shared<Loaded>();
  auto job = [load = std::move(load), loaded] {
    try {
      auto next = load();
      check::check_config(next);
      io::prepare_server_tls_contexts(next);  // for the stage, which runs on the loop
      loaded->config = std::move(next);
    } catch (const std::exception& e) {
      loaded->error = e.what();
    }
  };
  auto done = [this, loaded, origin = std::move(origin), refusal = std::move(refusal)] {
    if (!loaded->config) return finish(flow_.refuse(refusal, remote::errors_at(loaded->error, origin)));
    apply_config(std::move(*loaded->config));
  };
  off_loop(std::move(job), std::move(done));
}

void RemoteConfigCoordinator::apply_config(config::Config next) {
  if (config::writes_frozen(bridge_.config()))
    return finish(flow_.refuse("read_only is on: the bridge takes no change of its config from afar"));
  if (!store_) return finish(flow_.refuse("state.file is none: a config from afar could not be kept across a restart"));
  if (auto reason = locks_out(next, change_->source, change_->by)) return finish(flow_.refuse("refused: " + *reason));
  const auto proving_time = probe_of(next);
  change_->previous = bridge_.config();
  try {
    const auto level = next.log.level;
    bridge_.reload(std::move(next));
    platform::set_log_level(level);
  } catch (const std::exception& e) {
    change_->previous.reset();
    return finish(flow_.refuse(std::string("the config cannot be applied: ") + e.what()));
  }
  flow_.committed(std::chrono::steady_clock::now(), proving_time);
  probe();
}

void RemoteConfigCoordinator::probe() {
  auto facts = bridge_.probe_facts();
  if (flow_.probing() && remote::probe_shortfall(facts).empty()) return keep_then_answer(std::move(facts));
  auto answer = flow_.probe(facts, std::chrono::steady_clock::now());
  if (!answer) {
    probe_timer_.expires_after(probe_interval);
    probe_timer_.async_wait([this](const boost::system::error_code& ec) {
      if (!ec) probe();
    });
    return;
  }
  conclude(std::move(*answer));
}

// Keeping the config writes and fdatasyncs its text, its record, the record in force and
// their directory: on the loop that was a stall of 17-38 ms of every Modbus client at the
// moment of `applied` (bench/remote_config.py, docs/performance.md). So it runs on the
// worker; the flow is still probing meanwhile (another change is `busy`, a SIGHUP waits),
// and it answers, `applied` by the facts that passed, once the files are on the disk.
// The loop may read the store meanwhile (GET /api/config, `config history`): the store
// holds no state in memory, each file is replaced atomically, and a listing that meets an
// entry half written skips it.
void RemoteConfigCoordinator::keep_then_answer(remote::ProbeFacts passed) {
  struct Kept {
    std::optional<io::StoredConfig> stored;  // none for a revert: the operator's file is in force
    std::optional<std::string> error;
  };
  auto kept = std::make_shared<Kept>();
  // The remote config in force until now (none: the operator's file), which this one replaces.
  const auto replaced = in_force_.remote ? std::optional<unsigned>(in_force_.remote->number) : std::nullopt;
  auto keep = [store = &*store_, text = change_->text, source = change_->source, by = change_->by,
               file = in_force_.operator_file, sha256 = in_force_.operator_sha256, replaced, kept] {
    try {
      if (text) kept->stored = store->keep(*text, source, by, file, sha256, replaced, std::chrono::system_clock::now());
      else store->put_file_in_force();
    } catch (const std::exception& e) {
      kept->error = e.what();
    }
  };
  auto answer = [this, passed = std::move(passed), kept] {
    auto applied = flow_.probe(passed, std::chrono::steady_clock::now());
    if (kept->error) {
      applied->result = remote::Result::rolled_back;
      applied->reason = "the config could not be kept: " + *kept->error;
    } else {
      if (kept->stored) {
        in_force_.remote = std::move(kept->stored);
        reverted_from_.reset();
      } else {
        reverted_from_ = in_force_.remote;
        in_force_.remote.reset();
        in_force_.operator_sha256 = bridge_.config().file_sha256;
      }
      in_force_.config = bridge_.config();
    }
    conclude(std::move(*applied));
  };
  off_loop(std::move(keep), std::move(answer));
}

void RemoteConfigCoordinator::off_loop(io::CpuWorker::Job job, io::CpuWorker::Done done) {
  // One change at a time, and one step of it on the worker: it is never full. Were it, the
  // step runs here.
  if (worker_.submit(job, done)) return;
  job();
  done();
}

void RemoteConfigCoordinator::conclude(remote::ChangeAnswer answer) {
  if (answer.result == remote::Result::rolled_back) {
    try {
      const auto level = change_->previous->log.level;
      bridge_.reload(std::move(*change_->previous));
      platform::set_log_level(level);
    } catch (const std::exception& e) {
      // The previous config ran a moment ago; what it needs may have been taken since.
      spdlog::critical("remote config: going back to the previous config failed, the new one stays: {}", e.what());
      answer.reason += std::string("; going back failed, the new config runs: ") + e.what();
    }
  }
  finish(answer);
}

void RemoteConfigCoordinator::finish(const remote::ChangeAnswer& answer) {
  const auto done = std::move(change_->done);
  change_.reset();
  switch (answer.result) {
    case remote::Result::applied: ++status_.changes_applied; break;
    case remote::Result::refused: ++status_.changes_refused; break;
    case remote::Result::rolled_back: ++status_.changes_rolled_back; break;
    case remote::Result::busy: ++status_.changes_busy; break;
  }
  status_.last = remote::LastChange{answer.id, std::string(remote::result_name(answer.result)), answer.reason,
                                    std::string(remote::source_name(answer.source)), answer.by, now_utc()};
  const auto level = answer.result == remote::Result::applied ? spdlog::level::info : spdlog::level::warn;
  const auto kept = answer.result == remote::Result::applied
                        ? (in_force_.remote ? fmt::format(", kept as {}", in_force_.remote->text_path.string())
                                            : fmt::format(", the operator's file {} in force", in_force_.operator_file))
                        : std::string{};
  spdlog::log(level, "remote config: {} by {}: {}{}{}{} (sha256 {})", remote::source_name(answer.source), answer.by,
              remote::result_name(answer.result), kept, answer.reason.empty() ? "" : ": ", answer.reason, answer.id);
  for (const auto& error : answer.errors) spdlog::log(level, "  line {}, column {}: {}", error.line, error.column, error.message);
  reloaded();
  done(answer);
  if (after_change_) {
    auto task = std::move(*after_change_);
    after_change_.reset();
    task();
  }
}

void RemoteConfigCoordinator::run_when_free(std::function<void()> task) {
  if (!flow_.busy()) return task();
  spdlog::info("remote config: a change is under way; the reload follows its end");
  after_change_ = std::move(task);
}

void RemoteConfigCoordinator::reloaded() {
  if (store_ && in_force_.config.remote_config) store_->set_keep(in_force_.config.remote_config->keep);
  status_.sha256 = in_force_.config.file_sha256;
  status_.file = in_force_.remote ? in_force_.remote->text_path.string() : in_force_.operator_file;
  if (const auto& remote = in_force_.remote) {
    status_.source = std::string(remote::source_name(remote->source));
    status_.number = remote->number;
    status_.by = remote->by;
    status_.applied_at = remote->applied_at;
  } else {
    status_.source = "file";
    status_.number.reset();
    status_.by.reset();
    status_.applied_at.reset();
  }
  bridge_.config_in_force_changed();
}

remote::ConfigStatus RemoteConfigCoordinator::status() const { return status_; }

nlohmann::json RemoteConfigCoordinator::in_force(bool with_text) const {
  nlohmann::json j = status_;
  if (with_text) {
    try {
      j["text"] = in_force_.remote && store_ ? store_->text(*in_force_.remote) : config::read_config_file(in_force_.operator_file);
    } catch (const std::exception& e) {
      j["text"] = nullptr;
      j["text_error"] = e.what();
    }
  }
  return j;
}

// What the last change replaced, for the page's diff: the remote config in force before
// (its number), or the operator's file (number null) as long as it is still the file it was.
nlohmann::json RemoteConfigCoordinator::replaced() const {
  if (!store_) return nullptr;
  std::optional<unsigned> number;
  if (in_force_.remote) {
    if (!in_force_.remote->replaced_known)
      return {{"number", nullptr}, {"text", nullptr}, {"text_error", "its record does not say what it replaced"}};
    number = in_force_.remote->replaced_number;
  } else if (reverted_from_) {
    number = reverted_from_->number;
  } else {
    return nullptr;  // the operator's file, and no revert since the start: nothing to compare with
  }
  nlohmann::json replaced{{"number", number ? nlohmann::json(*number) : nlohmann::json(nullptr)}, {"text", nullptr}};
  try {
    if (number) {
      const auto stored = store_->entry(*number);
      if (!stored) throw std::runtime_error(fmt::format("remote config {} is no longer kept", *number));
      replaced["text"] = store_->text(*stored);
    } else {
      auto text = config::read_config_file(in_force_.operator_file);
      if (remote::change_id(text) != in_force_.remote->replaced_sha256)
        throw std::runtime_error(fmt::format("{} has changed since", in_force_.operator_file));
      replaced["text"] = std::move(text);
    }
  } catch (const std::exception& e) {
    replaced["text_error"] = e.what();
  }
  return replaced;
}

nlohmann::json RemoteConfigCoordinator::history() const {
  auto entries = nlohmann::json::array();
  if (store_) {
    const auto in_force = in_force_.remote ? in_force_.remote->number : 0;
    for (const auto& stored : store_->history())
      entries.push_back({{"number", stored.number},
                         {"id", stored.id},
                         {"source", remote::source_name(stored.source)},
                         {"by", stored.by},
                         {"applied_at", stored.applied_at},
                         {"replaced_file", stored.replaced_file},
                         {"replaced_sha256", stored.replaced_sha256},
                         {"in_force", stored.number == in_force}});
  }
  return {{"in_force", status_}, {"history", std::move(entries)}};
}

}  // namespace unima::app
