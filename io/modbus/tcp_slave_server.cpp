#include "io/modbus/tcp_slave_server.hpp"

#include <algorithm>
#include <array>
#include <cstring>
#include <fcntl.h>
#include <unistd.h>
#include <vector>

#include <spdlog/spdlog.h>

#include "io/lazy_deadline.hpp"
#include "io/state_file.hpp"
#include "io/tls_context.hpp"
#include "tls/memory_session.hpp"
#include "modbus/mbap.hpp"
#include "modbus/slave_session.hpp"
#include "platform/peer_warnings.hpp"

namespace unima::io {

using asio::ip::tcp;
using Clock = std::chrono::steady_clock;

class TcpSlaveServer::Connection : public std::enable_shared_from_this<Connection> {
 public:
  Connection(TcpSlaveServer& server, tcp::socket socket)
      : server_(server),
        socket_(std::move(socket)),
        idle_(socket_.get_executor(), [this] { return idle_deadline(); }, [this] { close_idle(); }) {
    boost::system::error_code ec;
    const auto remote = socket_.remote_endpoint(ec);
    peer_ = ec ? std::string("?") : remote.address().to_string() + ":" + std::to_string(remote.port());
    if (!ec) address_ = remote.address();
    socket_.set_option(tcp::no_delay(true), ec);
    // send() writes synchronously and must never block the loop (see send()).
    socket_.non_blocking(true, ec);
    if (server_.options_.tls) {
      tls_context_ = server_.options_.tls->context;  // a renewal may replace the server's
      tls_.emplace(tls_context_->native_handle());
      cipher_in_.resize(tls_record_room);
    }
  }

  void start() {
    last_activity_ = Clock::now();
    if (tls_) return handshake();
    idle_.watch();
    read();
  }

  void close() {
    boost::system::error_code ec;
    socket_.shutdown(tcp::socket::shutdown_both, ec);
    socket_.close(ec);
    idle_.cancel();
  }

  // The server stops and may be gone before this connection's pending handlers run
  // (aborted reads, a deferred read start): they must not call back into it.
  void abandon() {
    finished_ = true;
    close();
  }

  const std::string& peer() const { return peer_; }
  Clock::time_point last_activity() const { return last_activity_; }
  const asio::ip::address& address() const { return address_; }
  const std::optional<std::string>& role() const { return role_; }
  /// Closed by the server (for a new client, SPEC §10); the server logs why.
  void evict(const std::string& why) { finish(why); }

 private:
  // Boost 1.74's reactor tries the read at once (a recv) before it waits on epoll; when
  // the client waits for each answer, that try finds nothing. Waiting without it
  // (async_wait) would cost an epoll_ctl instead: this is the cheapest Asio allows
  // (docs/performance.md, "Tried and not kept").
  void read() {
    if (tls_) return read_records();
    socket_.async_read_some(asio::buffer(in_.data() + in_used_, in_.size() - in_used_),
                            [this, self = shared_from_this()](const boost::system::error_code& ec, std::size_t n) {
                              if (ec) return finish(ec == asio::error::eof ? "closed by the client" : ec.message());
                              in_used_ += n;
                              serve();
                            });
  }

  // Answers what in_ holds: at once, or once the state file holds what it wrote.
  void serve() {
    if (!process()) return finish_broken_stream();
    if (out_used_ == 0) return read();
    if (kept_as_ != 0) return send_once_durable();
    send();
  }

  // Over TLS the socket is read like a plain one, into cipher_in_, and the records go
  // through the session in memory (tls/memory_session): the same system calls as plain
  // Modbus/TCP, and no asynchronous operation of an SSL stream around each.
  void read_records() {
    if (plaintext_waits_) return take_plaintext();  // in_ was full before the session was read to its end
    socket_.async_read_some(asio::buffer(cipher_in_), [this, self = shared_from_this()](const boost::system::error_code& ec, std::size_t n) {
      if (ec) return finish(ec == asio::error::eof ? "closed by the client" : ec.message());
      tls_->feed(std::span(cipher_in_.data(), n));
      if (!tls_->handshaken()) return handshake_step();
      take_plaintext();
    });
  }

  void take_plaintext() {
    plaintext_waits_ = true;
    while (in_used_ < in_.size()) {
      std::size_t n = 0;
      const auto status = tls_->read(std::span(in_.data() + in_used_, in_.size() - in_used_), n);
      if (status == tls::MemorySession::Status::closed) return finish("closed by the client");
      if (status == tls::MemorySession::Status::failed) {
        // A record that does not authenticate is an attack or a broken path: the operator hears of it.
        send_alert();
        platform::warn_from_peer("modbus tls: broken sessions", peer_, "modbus tls: {} broke the session: {}; closing its connection",
                                 peer_, tls_->error());
        return finish("TLS: " + tls_->error());
      }
      if (status == tls::MemorySession::Status::want_input) {
        plaintext_waits_ = false;
        break;
      }
      in_used_ += n;
    }
    serve();
  }

  // Sends what the session wrote besides answers (its handshake flight), then reads on.
  void flush_records_then_read() {
    tls_->take_output(cipher_out_);
    if (cipher_out_.empty()) return read();
    boost::system::error_code ec;
    const std::size_t sent = socket_.write_some(asio::buffer(cipher_out_), ec);
    if (!ec && sent == cipher_out_.size()) {
      cipher_out_.clear();
      return read();
    }
    if (ec && ec != asio::error::would_block && ec != asio::error::try_again) return finish(ec.message());
    asio::async_write(socket_, asio::buffer(cipher_out_.data() + (ec ? 0 : sent), cipher_out_.size() - (ec ? 0 : sent)),
                      [this, self = shared_from_this()](const boost::system::error_code& e, std::size_t) {
                        if (e) return finish(e.message());
                        cipher_out_.clear();
                        read();
                      });
  }

  // The alert that tells the client why goes out before the connection closes, if the
  // socket takes it at once.
  void send_alert() {
    tls_->take_output(cipher_out_);
    boost::system::error_code ignored;
    if (!cipher_out_.empty()) socket_.write_some(asio::buffer(cipher_out_), ignored);
  }

  // SPEC §11: the client must show a certificate the CA signed, within frame_timeout like
  // any started request (a client stuck in the handshake holds no slot); its role then
  // says what it may write, and names it in the monitor and the log.
  void handshake() {
    adu_started_ = Clock::now();
    idle_.watch();
    read_records();
  }

  void handshake_step() {
    const auto status = tls_->handshake();
    if (status == tls::MemorySession::Status::failed || status == tls::MemorySession::Status::closed) {
      send_alert();
      const auto why = status == tls::MemorySession::Status::closed ? std::string("closed") : tls_->error();
      platform::warn_from_peer("modbus tls: failed handshakes", peer_, "modbus tls: {} failed the TLS handshake: {}", peer_, why);
      return finish("failed the TLS handshake");
    }
    if (status == tls::MemorySession::Status::want_input) return flush_records_then_read();
    const auto identity = tls::client_identity(tls_->native_handle());
    role_ = identity.role;
    spdlog::debug("modbus tls: {} connected as {} (role {}), {} on {}", peer_, identity.subject, role_ ? *role_ : "none",
                  SSL_get_version(tls_->native_handle()), tls_->records_own() ? "the port's record layer" : "OpenSSL's records");
    // The monitor's port field names the client: its role, or its certificate's subject.
    peer_ = (role_ ? *role_ : identity.subject) + "@" + peer_;
    handshaken_ = true;
    adu_started_.reset();
    last_activity_ = Clock::now();
    plaintext_waits_ = true;  // a request may have come with the client's Finished
    flush_records_then_read();
  }

  // Answers every complete request in the buffer, in order, into out_. False when the
  // stream is broken beyond re-synchronisation.
  bool process() {
    std::size_t at = 0;
    const auto& context = server_.context_;
    while (true) {
      const auto adu = modbus::parse_tcp_adu(std::span(in_.data() + at, in_used_ - at));
      if (adu.status == modbus::TcpAdu::Status::bad_header) {
        // Seed §5.3 note 2: a bad length is Err03; the monitor shows what came, unanswered.
        if (context.on_transaction)
          context.on_transaction(modbus::Transaction{
              port_kind(), peer_, std::chrono::system_clock::now(), modbus::TransactionState::err03,
              std::span<const std::uint8_t>(in_.data() + at, std::min(in_used_ - at, modbus::max_tcp_adu_size)), {}});
        return false;
      }
      if (adu.status == modbus::TcpAdu::Status::need_more) break;
      // The response PDU is built in place behind room for its MBAP header: no copy, and
      // out_ only grows (zero-filled) when a batch is longer than any before it.
      if (out_.size() < out_used_ + modbus::max_tcp_adu_size) out_.resize(out_used_ + modbus::max_tcp_adu_size);
      const auto adu_out = std::span(out_.data() + out_used_, modbus::max_tcp_adu_size);
      const auto pdu_out = adu_out.subspan(modbus::mbap_header_size, modbus::max_pdu_size);
      const auto unit = adu.header.unit_id;
      const auto served =
          modbus::serve_request(modbus::Link::tcp, modbus::recipient_of(modbus::Link::tcp, unit, context.unit_id),
                                adu.pdu, pdu_out, *context.registers, context.options, server_.write_rights(role_));
      if (served.fault && context.on_fault) context.on_fault();
      kept_as_ = std::max(kept_as_, served.kept_as);
      const auto size = modbus::write_mbap_header(adu.header.transaction_id, unit, served.length, adu_out) + served.length;
      if (context.on_transaction) {
        context.on_transaction(modbus::Transaction{port_kind(), peer_, std::chrono::system_clock::now(),
                                                   served.state, std::span<const std::uint8_t>(in_.data() + at, adu.size),
                                                   adu_out.first(size)});
      }
      out_used_ += size;
      at += adu.size;
    }
    if (at > 0) {
      std::memmove(in_.data(), in_.data() + at, in_used_ - at);
      in_used_ -= at;
    }
    note_progress(at > 0);
    return true;
  }

  // Only a complete request counts as activity: a client that sends a byte now and then
  // neither stays "active" nor holds its slot beyond frame_timeout (SPEC §10).
  void note_progress(bool served) {
    if (in_used_ == 0 && !served && !adu_started_) return;  // nothing came (a lone read of 0 bytes)
    const auto now = Clock::now();
    if (served) last_activity_ = now;
    if (in_used_ == 0) {
      adu_started_.reset();
    } else if (served || !adu_started_) {
      // A request has begun: its deadline is usually earlier than the idle one the timer
      // waits for, so the timer is armed again.
      adu_started_ = now;
      idle_.cancel();
      idle_.watch();
    }
  }

  // A write is acknowledged only once the state file holds it (SPEC §10); the answers
  // behind it in this batch wait with it, so they keep their order. A write the file could
  // not take is never acknowledged: the connection closes, and the master tries again.
  void send_once_durable() {
    answer_once_durable(server_.context_.state, std::exchange(kept_as_, 0), [this, self = shared_from_this()](bool durable) {
      if (finished_) return;
      if (!durable) return finish("its write could not be kept in the state file");
      send();
    });
  }

  // The answers nearly always fit the socket's send buffer, so they go out in one
  // non-blocking send right here and the connection goes straight back to reading: no
  // write operation and no completion handler to dispatch per request. Only when the
  // client does not keep up does the rest wait for the socket in async_write.
  void send() {
    if (tls_) {
      if (!tls_->write(std::span(out_.data(), out_used_))) return finish("TLS: " + tls_->error());
      tls_->take_output(cipher_out_);  // the answers' records, sent like plain answers
    }
    const auto bytes = outgoing();
    boost::system::error_code ec;
    const std::size_t sent = socket_.write_some(asio::buffer(bytes.data(), bytes.size()), ec);
    if (ec == asio::error::would_block || ec == asio::error::try_again || (!ec && sent < bytes.size()))
      return send_rest(ec ? 0 : sent);
    if (ec) return finish(ec.message());
    sent_all();
    // With other clients, the next read starts after the loop's other ready work, not
    // here: Asio tries a read at once (see read()), and a client that waits for each
    // answer has not sent its next request yet when this send returns, so that try would
    // be a wasted system call; after the others were served it often finds the request
    // (64 clients: 2.1 instead of 3.0 system calls a request). A lone client gains
    // nothing by it and would pay an extra epoll_wait.
    if (server_.connections_.size() == 1) return read();
    asio::post(socket_.get_executor(), [this, self = shared_from_this()] {
      if (!finished_) read();
    });
  }

  // What goes to the socket: the answers, or over TLS their records.
  std::span<const std::uint8_t> outgoing() const {
    return tls_ ? std::span<const std::uint8_t>(cipher_out_) : std::span<const std::uint8_t>(out_.data(), out_used_);
  }
  void sent_all() {
    out_used_ = 0;
    cipher_out_.clear();
  }

  // The bytes from `done` on, when the client does not keep up.
  void send_rest(std::size_t done) {
    const auto bytes = outgoing();
    asio::async_write(socket_, asio::buffer(bytes.data() + done, bytes.size() - done),
                      [this, self = shared_from_this()](const boost::system::error_code& ec, std::size_t) {
                        if (ec) return finish(ec.message());
                        sent_all();
                        read();
                      });
  }

  modbus::PortKind port_kind() const { return tls_ ? modbus::PortKind::tls : modbus::PortKind::tcp; }

  // Requests only move the deadline later, so the timer is not re-armed per request
  // (LazyDeadline). The limit is read at each check: a reload may have changed it.
  // A closed connection may outlive its server (stop() abandons it): it looks at nothing
  // of the server's once its socket is closed.
  std::optional<Clock::time_point> idle_deadline() const {
    if (!socket_.is_open()) return std::nullopt;
    std::optional<Clock::time_point> due;
    if (const auto idle = server_.options_.idle_timeout; idle.count() > 0) due = last_activity_ + idle;
    if (adu_started_) {
      const auto frame_due = *adu_started_ + server_.options_.frame_timeout;
      due = due ? std::min(*due, frame_due) : frame_due;
    }
    return due;
  }
  void close_idle() {
    if (tls_ && !handshaken_)
      platform::warn_from_peer("modbus tls: handshakes not completed in time", peer_,
                               "modbus tls: {} did not complete the TLS handshake within {} ms, closing", peer_,
                               server_.options_.frame_timeout.count());
    else if (adu_started_ && Clock::now() >= *adu_started_ + server_.options_.frame_timeout)
      platform::warn_from_peer(server_.warning("requests not completed in time"), peer_,
                               "{}: {} did not complete its request within {} ms, closing", server_.name(), peer_,
                               server_.options_.frame_timeout.count());
    else
      spdlog::info("{}: {} idle for {} ms, closing", server_.name(), peer_, server_.options_.idle_timeout.count());
    close();
  }

  void finish(const std::string& why) {
    if (finished_) return;
    finished_ = true;
    spdlog::debug("{}: {} disconnected: {}", server_.name(), peer_, why);
    close();
    server_.forget(this);
  }
  // A bad MBAP header cannot be skipped: the stream has no way back into step. It is a
  // fault of the client's (C+0x13 bit 15), and only its own connection closes.
  void finish_broken_stream() {
    if (finished_) return;
    platform::warn_from_peer(server_.warning("bad MBAP headers"), peer_,
                             "{}: {} sent a bad MBAP header; closing its connection", server_.name(), peer_);
    if (server_.context_.on_fault) server_.context_.on_fault();
    finish("sent a bad MBAP header");
  }

  TcpSlaveServer& server_;
  tcp::socket socket_;
  std::shared_ptr<asio::ssl::context> tls_context_;  // outlives tls_
  std::optional<tls::MemorySession> tls_;
  // A TLS record holds at most 16 KiB of plaintext and some bytes of its own; the socket
  // is read in such pieces (sized for TLS connections only).
  static constexpr std::size_t tls_record_room = 16 * 1024 + 512;
  std::vector<std::uint8_t> cipher_in_;
  std::vector<std::uint8_t> cipher_out_;  // records waiting for the socket
  bool plaintext_waits_ = false;          // the session may hold more than in_ took
  bool handshaken_ = false;
  std::optional<std::string> role_;  // from the client's certificate
  LazyDeadline idle_;
  std::string peer_;
  asio::ip::address address_;
  // A full ADU is at most 260 bytes; room for several pipelined ones per read. Left
  // uninitialised: only the in_used_ bytes a read filled are ever looked at, and a client
  // that sends little then keeps only the pages it touched resident (issue #8's RSS).
  std::array<std::uint8_t, 4096> in_;
  std::size_t in_used_ = 0;
  std::vector<std::uint8_t> out_;  // out_used_ bytes of answers, then spare room
  std::size_t out_used_ = 0;
  std::uint64_t kept_as_ = 0;  // what the writes among out_'s answers kept: they wait for it
  Clock::time_point last_activity_;
  std::optional<Clock::time_point> adu_started_;  // when the first bytes of an incomplete request came
  bool finished_ = false;
};

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

namespace {

// The peer's address in the allow list's form: IPv4 as ::ffff:a.b.c.d.
config::PeerAddress peer_address(const asio::ip::address& address) {
  if (address.is_v6()) return address.to_v6().to_bytes();
  config::PeerAddress bytes{};
  bytes[10] = bytes[11] = 0xFF;
  const auto v4 = address.to_v4().to_bytes();
  std::copy(v4.begin(), v4.end(), bytes.begin() + 12);
  return bytes;
}

}  // namespace

const modbus::WriteRights* TcpSlaveServer::write_rights(const std::optional<std::string>& role) const {
  if (options_.read_only) return &nothing_;
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
  if (connections_.size() >= options_.max_clients)
    evict_longest_idle(fmt::format("{} connections is the limit", options_.max_clients));
  auto connection = std::make_shared<Connection>(*this, std::move(socket));
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
