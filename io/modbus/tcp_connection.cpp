#include "io/modbus/tcp_connection.hpp"

#include <algorithm>
#include <cstring>

#include <spdlog/spdlog.h>

#include "io/state_file.hpp"
#include "modbus/mbap.hpp"
#include "modbus/slave_session.hpp"
#include "platform/peer_warnings.hpp"

namespace unima::io {

using asio::ip::tcp;

namespace {
// Clients of the gateway are told apart by the order they connected in.
std::uint64_t next_client_id = 1;
}  // namespace

TcpSlaveServer::Connection::Connection(TcpSlaveServer& server, tcp::socket socket)
    : server_(server),
      socket_(std::move(socket)),
      idle_(socket_.get_executor(), [this] { return idle_deadline(); }, [this] { close_idle(); }),
      client_id_(next_client_id++) {
  boost::system::error_code ec;
  const auto remote = socket_.remote_endpoint(ec);
  peer_ = ec ? std::string("?") : remote.address().to_string() + ":" + std::to_string(remote.port());
  if (!ec) address_ = remote.address();
  socket_.set_option(tcp::no_delay(true), ec);
  // send() writes synchronously and must never block the loop (see send()).
  socket_.non_blocking(true, ec);
}

void TcpSlaveServer::Connection::start() {
  last_activity_ = Clock::now();
  idle_.watch();
  read();
}

void TcpSlaveServer::Connection::close() {
  say_goodbye();
  boost::system::error_code ec;
  socket_.shutdown(tcp::socket::shutdown_both, ec);
  socket_.close(ec);
  idle_.cancel();
}

// Boost 1.74's reactor tries the read at once (a recv) before it waits on epoll; when
// the client waits for each answer, that try finds nothing. Waiting without it
// (async_wait) would cost an epoll_ctl instead: this is the cheapest Asio allows
// (docs/performance.md, "Tried and not kept").
void TcpSlaveServer::Connection::read() {
  socket_.async_read_some(asio::buffer(in_.data() + in_used_, in_.size() - in_used_),
                          [this, self = shared_from_this()](const boost::system::error_code& ec, std::size_t n) {
                            if (ec) return finish(ec == asio::error::eof ? "closed by the client" : ec.message());
                            in_used_ += n;
                            serve();
                          });
}

void TcpSlaveServer::Connection::serve() {
  if (!process()) return finish_broken_stream();
  if (forwarding_) return forward();
  if (out_used_ == 0) return read();
  if (waiting_) return send_once_durable();
  send();
}

// Answers every complete request in the buffer, in order, into out_, up to a write that
// waits for the state file. False when the stream is broken beyond re-synchronisation.
bool TcpSlaveServer::Connection::process() {
  std::size_t at = 0;
  const auto& context = server_.context_;
  while (true) {
    const auto adu = modbus::parse_tcp_adu(std::span(in_.data() + at, in_used_ - at));
    if (adu.status == modbus::TcpAdu::Status::bad_header) {
      // Seed §5.3 note 2: a bad length is Err03; the monitor shows what came, unanswered.
      if (context.on_transaction)
        context.on_transaction(modbus::Transaction{
            port_kind(), peer_, std::chrono::system_clock::now(), modbus::TransactionState::err03,
            std::span<const std::uint8_t>(in_.data() + at, std::min(in_used_ - at, modbus::max_tcp_adu_size)), {},
            false});
      return false;
    }
    if (adu.status == modbus::TcpAdu::Status::need_more) break;
    // The response PDU is built in place behind room for its MBAP header: no copy, and
    // out_ only grows (zero-filled) when a batch is longer than any before it.
    if (out_.size() < out_used_ + modbus::max_tcp_adu_size) out_.resize(out_used_ + modbus::max_tcp_adu_size);
    const auto adu_out = std::span(out_.data() + out_used_, modbus::max_tcp_adu_size);
    const auto pdu_out = adu_out.subspan(modbus::mbap_header_size, modbus::max_pdu_size);
    const auto unit = adu.header.unit_id;
    const auto recipient = modbus::recipient_of(modbus::Link::tcp, unit, context.unit_id);
    const auto* rights = server_.write_rights(role_);
    const auto& gateway = server_.context_.gateway;
    const auto verdict = modbus::route(recipient, unit, adu.pdu[0], routed_units(), rights,
                                       gateway && gateway->units[unit] && gateway->of(unit).reads_only);
    if (verdict == modbus::Verdict::forward) {
      auto& forwarding = forwarding_.emplace();
      forwarding.header = adu.header;
      forwarding.request_size = adu.size;
      std::copy_n(in_.data() + at, adu.size, forwarding.request.begin());
      at += adu.size;
      break;
    }
    const auto served =
        verdict == modbus::Verdict::refuse_forward ? modbus::refuse_forwarded_write(adu.pdu[0], pdu_out)
               : modbus::serve_request(modbus::Link::tcp, recipient, adu.pdu, pdu_out, *context.registers,
                                       context.options, rights, context.gateway != nullptr);
    const auto size = modbus::write_mbap_header(adu.header.transaction_id, unit, served.length, adu_out) + served.length;
    if (served.kept_as != 0) {
      auto& write = waiting_.emplace();
      write.kept_as = served.kept_as;
      write.answer_at = out_used_;
      write.header = adu.header;
      write.served = served;
      write.request_size = adu.size;
      std::copy_n(in_.data() + at, adu.size, write.request.begin());
      out_used_ += size;
      at += adu.size;
      break;
    }
    if (served.fault && context.on_fault) context.on_fault();
    if (context.on_transaction) {
      context.on_transaction(modbus::Transaction{port_kind(), peer_, std::chrono::system_clock::now(),
                                                 served.state, std::span<const std::uint8_t>(in_.data() + at, adu.size),
                                                 adu_out.first(size), served.length > 0});
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
void TcpSlaveServer::Connection::note_progress(bool served) {
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


// A write takes effect and is acknowledged only once the state file holds it (SPEC §10);
// the answers before it in this batch wait with it, so they keep their order. A write the
// file could not take changed nothing and is answered exception 04.
void TcpSlaveServer::Connection::send_once_durable() {
  answer_once_durable(server_.context_.state, waiting_->kept_as, [this, self = shared_from_this()](bool durable) {
    if (finished_) return;
    answer_waiting_write(durable);
    send();
  });
}

void TcpSlaveServer::Connection::answer_waiting_write(bool durable) {
  const auto write = *std::exchange(waiting_, std::nullopt);
  const auto adu_out = std::span(out_.data() + write.answer_at, modbus::max_tcp_adu_size);
  auto served = write.served;
  if (!durable) {
    // The answer ends out_: the exception takes its place.
    served = modbus::refuse_unkept_write(modbus::Recipient::this_slave, write.request[modbus::mbap_header_size],
                                         adu_out.subspan(modbus::mbap_header_size, modbus::max_pdu_size));
    out_used_ = write.answer_at +
                modbus::write_mbap_header(write.header.transaction_id, write.header.unit_id, served.length, adu_out) +
                served.length;
  }
  const auto& context = server_.context_;
  if (served.fault && context.on_fault) context.on_fault();
  if (context.on_transaction)
    context.on_transaction(modbus::Transaction{port_kind(), peer_, std::chrono::system_clock::now(), served.state,
                                               std::span<const std::uint8_t>(write.request.data(), write.request_size),
                                               adu_out.first(out_used_ - write.answer_at), served.length > 0});
}

// The plain and the TLS port forward alike (modbus::route decides, in process()).
const std::array<bool, 256>* TcpSlaveServer::Connection::routed_units() const {
  const auto& context = server_.context_;
  return context.gateway && context.line ? &context.gateway->units : nullptr;
}

void TcpSlaveServer::Connection::forward() {
  const auto& context = server_.context_;
  const auto& f = *forwarding_;
  const auto pdu = std::span(f.request.data() + modbus::mbap_header_size, f.request_size - modbus::mbap_header_size);
  // An empty allow list lets everyone in; an empty priority list puts nobody first.
  const auto& priority = context.gateway->of(f.header.unit_id).priority;
  GatewayRequest request{client_id_, peer_, !priority.empty() && priority.allows(peer_address(address_)),
                         f.header.unit_id, std::vector<std::uint8_t>(pdu.begin(), pdu.end())};
  context.line->forward(std::move(request), [this, self = shared_from_this()](std::span<const std::uint8_t> answer) {
    if (finished_) return;
    answer_forwarded(answer);
    send();
  });
  ++forwarded_count_;
  watch_while_forwarding();
}

void TcpSlaveServer::Connection::watch_while_forwarding() {
  if (finished_ || !forwarding_ || in_used_ == in_.size()) return;  // full: the rest waits in the socket
  socket_.async_wait(tcp::socket::wait_read,
                     [this, self = shared_from_this(), count = forwarded_count_](const boost::system::error_code& ec) {
                       // Answered meanwhile: the connection reads as usual again.
                       if (finished_ || !forwarding_ || count != forwarded_count_) return;
                       if (ec) return finish(ec.message());
                       take_while_forwarding();
                     });
}

void TcpSlaveServer::Connection::take_while_forwarding() {
  boost::system::error_code ec;
  const auto n = socket_.read_some(asio::buffer(in_.data() + in_used_, in_.size() - in_used_), ec);
  if (ec == asio::error::would_block || ec == asio::error::try_again) return watch_while_forwarding();
  if (ec) return finish(ec == asio::error::eof ? "closed by the client" : ec.message());
  in_used_ += n;
  watch_while_forwarding();
}

void TcpSlaveServer::Connection::answer_forwarded(std::span<const std::uint8_t> pdu) {
  const auto f = *std::exchange(forwarding_, std::nullopt);
  if (out_.size() < out_used_ + modbus::max_tcp_adu_size) out_.resize(out_used_ + modbus::max_tcp_adu_size);
  const auto adu_out = std::span(out_.data() + out_used_, modbus::max_tcp_adu_size);
  const auto length = std::min(pdu.size(), modbus::max_pdu_size);
  std::copy_n(pdu.begin(), length, adu_out.begin() + modbus::mbap_header_size);
  const auto size = modbus::write_mbap_header(f.header.transaction_id, f.header.unit_id, length, adu_out) + length;
  const auto& context = server_.context_;
  if (context.on_transaction)
    context.on_transaction(modbus::Transaction{port_kind(), peer_, std::chrono::system_clock::now(),
                                               modbus::state_of_response(pdu.first(length)),
                                               std::span<const std::uint8_t>(f.request.data(), f.request_size),
                                               adu_out.first(size), true});
  out_used_ += size;
}

// Requests that waited behind a write are in in_ already: they are served before more is
// read.
void TcpSlaveServer::Connection::read_more() {
  if (in_used_ > 0) return serve();
  read();
}


// The answers nearly always fit the socket's send buffer, so they go out in one
// non-blocking send right here and the connection goes straight back to reading: no
// write operation and no completion handler to dispatch per request. Only when the
// client does not keep up does the rest wait for the socket in async_write.
void TcpSlaveServer::Connection::send() {
  if (!seal()) return;
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
  if (server_.connections_.size() == 1) return read_more();
  asio::post(socket_.get_executor(), [this, self = shared_from_this()] {
    if (!finished_) read_more();
  });
}


// The bytes from `done` on, when the client does not keep up.
void TcpSlaveServer::Connection::send_rest(std::size_t done) {
  const auto bytes = outgoing();
  asio::async_write(socket_, asio::buffer(bytes.data() + done, bytes.size() - done),
                    [this, self = shared_from_this()](const boost::system::error_code& ec, std::size_t) {
                      if (ec) return finish(ec.message());
                      sent_all();
                      read_more();
                    });
}


// Requests only move the deadline later, so the timer is not re-armed per request
// (LazyDeadline). The limit is read at each check: a reload may have changed it.
// A closed connection may outlive its server (stop() abandons it): it looks at nothing
// of the server's once its socket is closed.
std::optional<TcpSlaveServer::Connection::Clock::time_point> TcpSlaveServer::Connection::idle_deadline() const {
  if (!socket_.is_open() || waiting_for_worker()) return std::nullopt;
  std::optional<Clock::time_point> due;
  if (const auto idle = server_.options_.idle_timeout; idle.count() > 0) due = last_activity_ + idle;
  if (adu_started_) {
    const auto frame_due = *adu_started_ + server_.options_.frame_timeout;
    due = due ? std::min(*due, frame_due) : frame_due;
  }
  return due;
}
void TcpSlaveServer::Connection::close_idle() {
  if (handshake_pending())
    platform::warn_from_peer("modbus tls: handshakes not completed in time", peer_,
                             "modbus tls: {} did not complete the TLS handshake within {} ms, closing", peer_,
                             server_.options_.frame_timeout.count());
  else if (adu_started_ && Clock::now() >= *adu_started_ + server_.options_.frame_timeout)
    platform::warn_from_peer(server_.warning("requests not completed in time"), peer_,
                             "{}: {} did not complete its request within {} ms, closing", server_.name(), peer_,
                             server_.options_.frame_timeout.count());
  else
    platform::note_from_peer(server_.warning("idle clients closed"), peer_, "{}: {} idle for {} ms, closing",
                             server_.name(), peer_, server_.options_.idle_timeout.count());
  close();
}

void TcpSlaveServer::Connection::finish(const std::string& why) {
  if (finished_) return;
  finished_ = true;
  spdlog::debug("{}: {} disconnected: {}", server_.name(), peer_, why);
  if (forwarding_ && server_.context_.line) server_.context_.line->client_gone(client_id_);
  close();
  server_.forget(this);
}
// A bad MBAP header cannot be skipped: the stream has no way back into step. It is a
// fault of the client's (C+0x13 bit 15), and only its own connection closes.
void TcpSlaveServer::Connection::finish_broken_stream() {
  if (finished_) return;
  platform::warn_from_peer(server_.warning("bad MBAP headers"), peer_,
                           "{}: {} sent a bad MBAP header; closing its connection", server_.name(), peer_);
  if (server_.context_.on_fault) server_.context_.on_fault();
  finish("sent a bad MBAP header");
}


}  // namespace unima::io
