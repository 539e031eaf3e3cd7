#pragma once
// A running part of the bridge (the Modbus ports, the master, the UnimaBUS transport, the
// state file, the status socket, HTTP, MQTT …): built from the running config when the
// bridge is, then reloaded in two halves so that a bad new config changes nothing.
//
// app::Bridge::reload: every service stages the next config (all that can fail: files
// read, ports bound, lines opened) while the running one keeps serving; when one throws,
// each service staged so far — the one that threw included — abandons, in reverse order,
// and the running config stays. Else the banks are swapped and every service commits,
// which cannot fail.

#include "io/runtime.hpp"
#include "remote/change_flow.hpp"
#include "status/document.hpp"

namespace unima::io {

class Service {
 public:
  virtual ~Service() = default;

  virtual void start() = 0;
  virtual void stop() = 0;

  /// Prepares `next` beside what runs; throws (std::exception) to refuse the reload.
  virtual void stage(const Banks& next) = 0;
  /// Gives back what stage took or built (a port it let go of so the new one could bind
  /// it); safe after a stage that threw half-way.
  virtual void abandon() {}
  /// Switches to what stage prepared; the runtime's banks are the next config's by now,
  /// `previous` the ones they replaced. Cannot fail.
  virtual void commit(const Banks& previous) = 0;

  /// Fills this service's part of the status document.
  virtual void describe(status::Document& status) const { (void)status; }

  /// What the probe of a config from afar (SPEC §19) needs of this service: its listener
  /// bound, its broker connected, its server answering. A service with none adds nothing.
  virtual void probe(remote::ProbeFacts& facts) const { (void)facts; }

  /// The config in force or the last change from afar is other than it was (a change from
  /// afar ended, a SIGHUP reloaded): what this service tells others of it is told anew.
  virtual void config_in_force_changed() {}
};

}  // namespace unima::io
