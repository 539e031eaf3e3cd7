#pragma once
// The running bridge: the banks of one config and the services that serve them, on one
// io_context (io/service.hpp). A reload builds the new config's banks beside the old;
// every service stages what it needs of the new config, and only when all could, the
// values carry over, the banks swap and every service commits.

#include <memory>
#include <vector>

#include "status/document.hpp"

#include "config/config.hpp"
#include "io/runtime.hpp"
#include "io/service.hpp"
#include "platform/asio.hpp"

namespace unima::app {

class Bridge {
 public:
  /// Builds everything and binds the ports; throws (std::exception) when it cannot.
  Bridge(asio::io_context& io, config::Config config);
  ~Bridge();

  void start();
  void stop();
  /// Switches to `config`; throws, leaving the running config untouched, when it cannot.
  void reload(config::Config config);

  const config::Config& config() const { return runtime_.config(); }
  /// The flow of configs from afar, for the channels (io::Runtime::config_changes).
  void take_config_changes(io::ConfigChanges* changes) { runtime_.config_changes = changes; }
  /// The front panel and counters as one document (`unima-bridge status`, /api/status,
  /// /metrics, the page).
  status::Document status() const;
  /// What the probe of a config from afar looks at, from every service (SPEC §19).
  remote::ProbeFacts probe_facts() const;
  /// Tells every service that the config in force, or the last change, is other than it was.
  void config_in_force_changed();

 private:
  io::Runtime runtime_;
  std::vector<std::unique_ptr<io::Service>> services_;  // in the order they start; they stop in reverse
  bool started_ = false;
};

}  // namespace unima::app
