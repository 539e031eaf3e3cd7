#include "io/tcp_slave_server.hpp"

#include <algorithm>
#include <array>
#include <cstring>
#include <vector>

#include <spdlog/spdlog.h>

#include "modbus/mbap.hpp"

namespace unima::io {

using asio::ip::tcp;
using Clock = std::chrono::steady_clock;

class TcpSlaveServer::Connection : public std::enable_shared_from_this<Connection> {
 public:
  Connection(TcpSlaveServer& server, tcp::socket socket)
      : server_(server), socket_(std::move(socket)), idle_timer_(socket_.get_executor()) {
    boost::system::error_code ec;
    const auto remote = socket_.remote_endpoint(ec);
    peer_ = ec ? std::string("?") : remote.address().to_string() + ":" + std::to_string(remote.port());
    socket_.set_option(tcp::no_delay(true), ec);
    // send() writes synchronously and must never block the loop (see send()).
    socket_.non_blocking(true, ec);
  }

  void start() {
    last_activity_ = Clock::now();
    arm_idle_timer(server_.options_.idle_timeout);
    read();
  }

  void close() {
    boost::system::error_code ec;
    socket_.shutdown(tcp::socket::shutdown_both, ec);
    socket_.close(ec);
    idle_timer_.cancel();
  }

  // The server stops and may be gone before this connection's pending handlers run
  // (aborted reads, a deferred read start): they must not call back into it.
  void abandon() {
    finished_ = true;
    close();
  }

  const std::string& peer() const { return peer_; }

 private:
  // Boost 1.74's reactor tries the read at once (a recv) before it waits on epoll; when
  // the client waits for each answer, that try finds nothing. Waiting without it
  // (async_wait) would cost an epoll_ctl instead: this is the cheapest Asio allows
  // (docs/performance.md, "Why not more at depth 1").
  void read() {
    socket_.async_read_some(asio::buffer(in_.data() + in_used_, in_.size() - in_used_),
                            [this, self = shared_from_this()](const boost::system::error_code& ec, std::size_t n) {
                              if (ec) return finish(ec == asio::error::eof ? "closed by the client" : ec.message());
                              in_used_ += n;
                              last_activity_ = Clock::now();
                              if (!process()) return finish("sent a bad MBAP header");
                              if (out_used_ == 0) return read();
                              send();
                            });
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
              modbus::PortKind::tcp, peer_, std::chrono::system_clock::now(), modbus::TransactionState::err03,
              std::span<const std::uint8_t>(in_.data() + at, std::min(in_used_ - at, modbus::max_tcp_adu_size)), {}});
        return false;
      }
      if (adu.status == modbus::TcpAdu::Status::need_more) break;
      // The response PDU is built in place behind room for its MBAP header: no copy, and
      // out_ only grows (zero-filled) when a batch is longer than any before it.
      if (out_.size() < out_used_ + modbus::max_tcp_adu_size) out_.resize(out_used_ + modbus::max_tcp_adu_size);
      const auto adu_out = std::span(out_.data() + out_used_, modbus::max_tcp_adu_size);
      const auto pdu_out = adu_out.subspan(modbus::mbap_header_size, modbus::max_pdu_size);
      std::size_t length = 0;
      const auto unit = adu.header.unit_id;
      if (unit == context.unit_id || unit == modbus::unit_id_any || unit == modbus::unit_id_not_used) {
        length = modbus::handle_request(adu.pdu, pdu_out, *context.registers, context.options);
      } else {
        // SPEC §3: a unit id that is not ours is Not4Me, answered "gateway target failed".
        length = modbus::write_exception(adu.pdu[0], modbus::ExceptionCode::gateway_target_failed, pdu_out);
      }
      const auto state = modbus::state_of_response(pdu_out.first(length));
      if (state != modbus::TransactionState::done && context.on_fault) context.on_fault();
      const auto size = modbus::write_mbap_header(adu.header.transaction_id, unit, length, adu_out) + length;
      if (context.on_transaction) {
        context.on_transaction(modbus::Transaction{modbus::PortKind::tcp, peer_, std::chrono::system_clock::now(),
                                                   state, std::span<const std::uint8_t>(in_.data() + at, adu.size),
                                                   adu_out.first(size)});
      }
      out_used_ += size;
      at += adu.size;
    }
    if (at > 0) {
      std::memmove(in_.data(), in_.data() + at, in_used_ - at);
      in_used_ -= at;
    }
    return true;
  }

  // The answers nearly always fit the socket's send buffer, so they go out in one
  // non-blocking send right here and the connection goes straight back to reading: no
  // write operation and no completion handler to dispatch per request. Only when the
  // client does not keep up does the rest wait for the socket in async_write.
  void send() {
    boost::system::error_code ec;
    const std::size_t sent = socket_.write_some(asio::buffer(out_.data(), out_used_), ec);
    if (ec == asio::error::would_block || ec == asio::error::try_again || (!ec && sent < out_used_)) {
      const std::size_t done = ec ? 0 : sent;
      asio::async_write(socket_, asio::buffer(out_.data() + done, out_used_ - done),
                        [this, self = shared_from_this()](const boost::system::error_code& ec, std::size_t) {
                          if (ec) return finish(ec.message());
                          out_used_ = 0;
                          read();
                        });
      return;
    }
    if (ec) return finish(ec.message());
    out_used_ = 0;
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

  // The timer is not re-armed per request (that would cost a timerfd call each time); on
  // expiry it looks at the last activity and waits for the remainder.
  void arm_idle_timer(Clock::duration after) {
    if (server_.options_.idle_timeout.count() == 0) return;
    idle_timer_.expires_after(after);
    std::weak_ptr<Connection> weak = shared_from_this();
    idle_timer_.async_wait([this, weak](const boost::system::error_code& ec) {
      const auto self = weak.lock();
      if (ec || !self || !socket_.is_open() || server_.options_.idle_timeout.count() == 0) return;
      const auto idle = Clock::now() - last_activity_;
      if (idle >= server_.options_.idle_timeout) {
        spdlog::info("modbus tcp: {} idle for {} ms, closing", peer_, server_.options_.idle_timeout.count());
        close();
        return;
      }
      arm_idle_timer(server_.options_.idle_timeout - idle);
    });
  }

  void finish(const std::string& why) {
    if (finished_) return;
    finished_ = true;
    spdlog::debug("modbus tcp: {} disconnected: {}", peer_, why);
    if (why == "sent a bad MBAP header") {
      spdlog::warn("modbus tcp: {} sent a bad MBAP header; closing its connection", peer_);
      if (server_.context_.on_fault) server_.context_.on_fault();
    }
    close();
    server_.forget(this);
  }

  TcpSlaveServer& server_;
  tcp::socket socket_;
  asio::steady_timer idle_timer_;
  std::string peer_;
  // A full ADU is at most 260 bytes; room for several pipelined ones per read. Left
  // uninitialised: only the in_used_ bytes a read filled are ever looked at, and a client
  // that sends little then keeps only the pages it touched resident (issue #8's RSS).
  std::array<std::uint8_t, 4096> in_;
  std::size_t in_used_ = 0;
  std::vector<std::uint8_t> out_;  // out_used_ bytes of answers, then spare room
  std::size_t out_used_ = 0;
  Clock::time_point last_activity_;
  bool finished_ = false;
};

TcpSlaveServer::TcpSlaveServer(asio::io_context& io, const TcpSlaveOptions& options, const SlaveContext& context)
    : io_(io), options_(options), context_(context), acceptor_(io), accept_retry_(io) {
  const tcp::endpoint endpoint(asio::ip::make_address(options_.listen), options_.port);
  acceptor_.open(endpoint.protocol());
  acceptor_.set_option(tcp::acceptor::reuse_address(true));
  acceptor_.bind(endpoint);
  acceptor_.listen(asio::socket_base::max_listen_connections);
}

TcpSlaveServer::~TcpSlaveServer() { stop(); }

std::uint16_t TcpSlaveServer::port() const {
  boost::system::error_code ec;
  return acceptor_.local_endpoint(ec).port();
}

void TcpSlaveServer::start() {
  spdlog::info("modbus tcp: serving unit {} on {}:{}", context_.unit_id, options_.listen, port());
  accept();
}

void TcpSlaveServer::stop() {
  if (stopped_) return;
  stopped_ = true;
  boost::system::error_code ec;
  acceptor_.close(ec);
  accept_retry_.cancel();
  auto connections = std::move(connections_);
  for (const auto& c : connections) c->abandon();
}

void TcpSlaveServer::accept() {
  acceptor_.async_accept([this](const boost::system::error_code& ec, tcp::socket socket) {
    if (ec == asio::error::operation_aborted || stopped_) return;
    if (ec) {
      // Out of descriptors or memory: the pending connection stays in the backlog, so an
      // immediate retry would fail again at once and spin. Wait a moment instead.
      spdlog::warn("modbus tcp: accept failed: {}; retrying in 100 ms", ec.message());
      accept_retry_.expires_after(std::chrono::milliseconds(100));
      accept_retry_.async_wait([this](const boost::system::error_code& wait_ec) {
        if (!wait_ec && !stopped_) accept();
      });
      return;
    }
    if (connections_.size() >= options_.max_clients) {
      spdlog::warn("modbus tcp: refusing a client: {} connections is the limit", options_.max_clients);
      boost::system::error_code ignored;
      socket.close(ignored);
    } else {
      auto connection = std::make_shared<Connection>(*this, std::move(socket));
      spdlog::debug("modbus tcp: {} connected", connection->peer());
      connections_.insert(connection);
      connection->start();
    }
    accept();
  });
}

void TcpSlaveServer::forget(Connection* connection) {
  for (auto it = connections_.begin(); it != connections_.end(); ++it)
    if (it->get() == connection) {
      connections_.erase(it);
      return;
    }
}

}  // namespace unima::io
