#include "io/modbus/tcp_slave_server.hpp"

#include "io/handshake_admission.hpp"
#include "io/modbus/tcp_connection.hpp"

#include <algorithm>
#include <fcntl.h>
#include <unistd.h>
#include <vector>

#include <spdlog/spdlog.h>

#include "platform/peer_warnings.hpp"

namespace unima::io {

using asio::ip::tcp;
using Clock = std::chrono::steady_clock;

TcpSlaveServer::TcpSlaveServer(asio::io_context& io, const TcpSlaveOptions& options, const SlaveContext& context)
    : io_(io), options_(options), context_(context), acceptor_(io),
      accepting_(acceptor_, name(), [this](asio::ip::tcp::socket socket) { adopt(std::move(socket)); },
                 [this] { return make_room(); }),
      reserve_fd_(::open("/dev/null", O_RDONLY | O_CLOEXEC)) {
  const tcp::endpoint endpoint(asio::ip::make_address(options_.listen), options_.port);
  acceptor_.open(endpoint.protocol());
  acceptor_.set_option(tcp::acceptor::reuse_address(true));
  acceptor_.bind(endpoint);
  acceptor_.listen(asio::socket_base::max_listen_connections);
}

TcpSlaveServer::~TcpSlaveServer() {
  stop();
  if (reserve_fd_ >= 0) ::close(reserve_fd_);
}

std::uint16_t TcpSlaveServer::port() const {
  boost::system::error_code ec;
  return acceptor_.local_endpoint(ec).port();
}

void TcpSlaveServer::start() {
  spdlog::info("{}: serving unit {} on {}:{}{}{}", name(), context_.unit_id, options_.listen, port(),
               options_.read_only ? ", read only" : "",
               options_.allow.empty() ? "" : fmt::format(", to {} allowed address ranges", options_.allow.ranges.size()));
  accepting_.start();
}

void TcpSlaveServer::stop() {
  if (stopped_) return;
  stopped_ = true;
  boost::system::error_code ec;
  accepting_.stop();
  acceptor_.close(ec);
  for (const auto& c : connections_.take_all()) c->abandon();
}

config::PeerAddress peer_address(const asio::ip::address& address) {
  if (address.is_v6()) return address.to_v6().to_bytes();
  config::PeerAddress bytes{};
  bytes[10] = bytes[11] = 0xFF;
  const auto v4 = address.to_v4().to_bytes();
  std::copy(v4.begin(), v4.end(), bytes.begin() + 12);
  return bytes;
}

const modbus::WriteRights* TcpSlaveServer::write_rights(const std::optional<std::string>& role) const {
  // The bridge-wide freeze (modbus.tcp.read_only) holds on every port; the banks' write
  // path refuses by it too, but a write forwarded to the line passes no write path.
  if (options_.read_only || context_.writes_frozen) return &nothing_;
  if (!options_.tls) return nullptr;
  if (!role) return &nothing_;
  const auto rights = options_.tls->roles.find(*role);
  return rights == options_.tls->roles.end() ? &nothing_ : &rights->second;
}

bool TcpSlaveServer::allowed(const asio::ip::address& address, const std::string& peer) const {
  if (options_.allow.allows(peer_address(address))) return true;
  const auto* key = options_.tls ? "modbus.tls.allow" : "modbus.tcp.allow";
  platform::warn_from_peer(warning(fmt::format("peers not in {}", key)), peer,
                           "{}: {} is not in {}; closing its connection", name(), peer, key);
  return false;
}

void TcpSlaveServer::set_access(const config::PeerAllowList& allow, bool read_only) {
  options_.allow = allow;
  options_.read_only = read_only;
  // A narrower list takes effect at once: the peers it leaves out are cut.
  std::vector<std::shared_ptr<Connection>> refused;
  for (const auto& connection : connections_)
    if (!allowed(connection->address(), connection->peer())) refused.push_back(connection);
  for (const auto& connection : refused) connection->evict("not in the allow list after a reload");
}

void TcpSlaveServer::adopt(tcp::socket socket) {
  if (reserve_fd_ < 0) reserve_fd_ = ::open("/dev/null", O_RDONLY | O_CLOEXEC);  // back once one is free
  boost::system::error_code ec;
  const auto remote = socket.remote_endpoint(ec);
  if (ec) return;  // gone already
  if (!allowed(remote.address(), remote.address().to_string() + ":" + std::to_string(remote.port()))) {
    socket.close(ec);
    return;
  }
  // Before any eviction: a refused handshake must not cost another client its slot.
  std::optional<tls::HandshakeSlot> handshake;
  if (options_.tls) {
    handshake = admit_handshake(options_.tls->handshakes, remote.address(),
                                remote.address().to_string() + ":" + std::to_string(remote.port()), name());
    if (!handshake) {
      socket.close(ec);
      return;
    }
  }
  if (connections_.size() >= options_.max_clients)
    evict_longest_idle(fmt::format("{} connections is the limit", options_.max_clients));
  auto connection = options_.tls ? make_tls_connection(*this, std::move(socket), std::move(*handshake))
                                 : std::make_shared<Connection>(*this, std::move(socket));
  spdlog::debug("{}: {} connected", name(), connection->peer());
  connections_.add(connection);
  connection->start();
}

bool TcpSlaveServer::evict_longest_idle(const std::string& why) {
  const auto idlest = connections_.idlest();
  if (!idlest) return false;
  const auto idle_ms =
      std::chrono::duration_cast<std::chrono::milliseconds>(Clock::now() - idlest->last_activity()).count();
  platform::warn_from_peer(warning("connections closed for a new client"), idlest->peer(),
                           "{}: {}: closing {}, idle for {} ms, for a new client", name(), why, idlest->peer(), idle_ms);
  idlest->evict("closed for a new client");
  return true;
}

bool TcpSlaveServer::make_room() {
  if (evict_longest_idle("out of file descriptors")) return true;
  if (reserve_fd_ < 0) return false;
  platform::warn_from_peer(warning("out of file descriptors"), "",
                           "{}: out of file descriptors: a new client takes the one held in reserve", name());
  ::close(reserve_fd_);
  reserve_fd_ = -1;
  return true;
}

void TcpSlaveServer::forget(Connection* connection) { connections_.forget(connection); }

}  // namespace unima::io
