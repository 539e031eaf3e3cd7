#pragma once
// The Modbus TCP slave (`modbus.tcp`, SPEC §3) or its Modbus/TCP Security twin
// (`modbus.tls`, SPEC §11) as a service. A reload keeps the listener and its connections
// when the address and port did not change (limits, allow list, read-only, roles and
// renewed certificates apply at once); a new address or port binds a new listener, the
// running one letting go of the port until the reload commits or is abandoned.

#include <memory>
#include <optional>

#include "io/cpu_worker.hpp"
#include "io/modbus/tcp_slave_server.hpp"
#include "io/movable_listener.hpp"
#include "io/service.hpp"

namespace unima::io {

class TcpSlaveService final : public Service {
 public:
  enum class Security { plain, tls };

  TcpSlaveService(Runtime& runtime, Security security);

  void start() override;
  void stop() override;
  void stage(const Banks& next) override;
  void abandon() override;
  void commit(const Banks& previous) override;
  void describe(status::Document& status) const override;
  void probe(remote::ProbeFacts& facts) const override;

 private:
  /// `config`'s slave on this port, or null when it has none; throws when it cannot listen.
  std::unique_ptr<TcpSlaveServer> make_server(const config::Config& config) const;
  /// The port's connection settings in `config` (modbus.tcp, or modbus.tls.connection).
  const config::TcpSlaveConfig* settings(const config::Config& config) const;

  Runtime& runtime_;
  Security security_;
  // Made before the first server and given to each: a reload that moves the port keeps
  // what its hosts spent and the counts.
  std::shared_ptr<tls::HandshakeLimiter> handshakes_ = std::make_shared<tls::HandshakeLimiter>();
  // Where the port's handshakes are computed, off the loop (io/cpu_worker), across reloads
  // like the limiter; as many queued as the limiter lets be in progress. Made before the
  // server and so destroyed after it: a stopped port's connections are closed before their
  // steps still out are dropped.
  std::shared_ptr<CpuWorker> handshake_worker_ =
      security_ == Security::tls ? std::make_shared<CpuWorker>(runtime_.io, handshakes_->limits().in_progress,
                                                                     CpuWorker::Priority::beside_the_loop)
                                 : nullptr;
  MovableListener<TcpSlaveServer> server_;
  std::shared_ptr<asio::ssl::context> next_context_;  // staged, same endpoint: the TLS files read again
};

}  // namespace unima::io
