#pragma once
// The one flow of SPEC §19 with its effects: a config sent from afar (or the operator's
// file, on a revert) is checked as `unima-bridge check` checks it, applied as a reload,
// probed, and then kept — or the bridge goes back to the config before. remote::ChangeFlow
// decides each step; this does the reloads, runs the probe's timer, keeps what was
// applied in the state directory (io::RemoteConfigStore) and says in the status
// document which config is in force.
//
// Everything runs on the loop but two steps that every Modbus client would otherwise wait
// for, which run on a worker thread while the flow stays busy: the load and check of the
// config (it reads every file the config names, and OpenSSL parses its certificates and
// keys: milliseconds), and the writes that keep an applied config (a few files written and
// fdatasync'ed: tens of milliseconds on a slow disk). A reload is the same as SIGHUP's
// (app::Bridge::reload); a SIGHUP that comes while a change is under way waits for its end
// (run_when_free).

#include <chrono>
#include <functional>
#include <optional>
#include <string>

#include "app/bridge.hpp"
#include "app/config_in_force.hpp"
#include "io/config_changes.hpp"
#include "io/cpu_worker.hpp"
#include "io/remote_config_store.hpp"
#include "platform/asio.hpp"
#include "remote/change_flow.hpp"
#include "remote/config_status.hpp"

namespace unima::app {

class RemoteConfigCoordinator final : public io::ConfigChanges {
 public:
  static constexpr std::chrono::milliseconds probe_interval{200};

  /// `in_force` is main's: a SIGHUP's reload changes it too.
  RemoteConfigCoordinator(asio::io_context& io, Bridge& bridge, ConfigInForce& in_force);
  ~RemoteConfigCoordinator() override;

  void apply(std::string text, remote::Source source, std::string by, Done done) override;
  void revert(remote::Source source, std::string by, Done done) override;
  nlohmann::json in_force(bool with_text) const override;
  nlohmann::json history() const override;
  nlohmann::json replaced() const override;
  remote::ConfigStatus status() const override;

  /// Runs `task` now, or when the change under way has ended (a SIGHUP's reload).
  void run_when_free(std::function<void()> task);
  /// The config in force changed by another way (a SIGHUP's reload): shown from now on,
  /// and told to the services (the MQTT birth).
  void reloaded();

 private:
  // `load` (a parse of the text) and the check of what it gives, on worker_; then
  // apply_config on the loop, or the change refused with `refusal` and the errors' lines
  // and columns in `origin`.
  void load_then_apply(std::function<config::Config()> load, std::string origin, std::string refusal);
  // A change whose config has loaded and passed the check: the rules of admission, the
  // reload and the probe.
  void apply_config(config::Config next);
  void probe();
  // The probe passed with `passed`: the config is kept (on worker_), then answered.
  void keep_then_answer(remote::ProbeFacts passed);
  // `job` on worker_, then `done` on the loop.
  void off_loop(io::CpuWorker::Job job, io::CpuWorker::Done done);
  // The flow's answer: back to the previous config when rolled back, then finish.
  void conclude(remote::ChangeAnswer answer);
  void finish(const remote::ChangeAnswer& answer);

  Bridge& bridge_;
  ConfigInForce& in_force_;
  remote::ChangeFlow flow_;
  asio::steady_timer probe_timer_;
  std::optional<io::RemoteConfigStore> store_;  // none when state.file is none: nothing can be kept
  // The change under way: how to answer, what to go back to, what to keep.
  struct Change {
    Done done;
    std::optional<config::Config> previous;
    std::optional<std::string> text;  // a config from afar; none: the operator's file (revert)
    remote::Source source = remote::Source::cli;
    std::string by;
  };
  std::optional<Change> change_;
  std::optional<std::function<void()>> after_change_;
  // The remote config the last revert (since the start) put out of force: the diff's old side.
  std::optional<io::StoredConfig> reverted_from_;
  remote::ConfigStatus status_;
  // Last: destroyed first, so that the load or keep it runs ends before store_ goes.
  io::CpuWorker worker_;
};

}  // namespace unima::app
