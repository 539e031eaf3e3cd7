// A client of a Modbus/TCP Security port (SPEC §11): the socket is read and written
// exactly as for plain Modbus/TCP, and the records go through a tls::MemorySession between
// the socket and the Modbus connection, which sees requests and answers only. The client
// must complete its handshake within frame_timeout like any started request (a client
// stuck in the handshake holds no slot), and its certificate's role says what it may write.
// Every record is OpenSSL's; a clean close (idle, evicted, the port stopped, the client's own
// close_notify) sends this side's close_notify first.
//
// A handshake step (an ECDHE key pair and a signature: ~1–2.5 ms of CPU) is computed on the
// port's io::CpuWorker, not on the loop that serves every Modbus client (issue 29). While a
// step is out the worker has the session to itself: the loop touches nothing of tls_ (no
// read of the socket either — the handshake is request and answer), and a close meanwhile
// (an eviction, the port stopped) closes the socket and says no goodbye. The client's
// deadline does not run while its step is out (issue 43: on a busy box a handshake that
// waited behind others on the worker was cut, though the client was never late). The
// step's completion holds the connection alive until it is back on the loop; one that
// comes back to a closed connection ends it there (if nothing had yet), and the
// handshake's slot ends as failed with the connection, once.

#include <spdlog/spdlog.h>

#include "io/cpu_worker.hpp"
#include "io/modbus/tcp_connection.hpp"
#include "platform/log_text.hpp"
#include "platform/peer_warnings.hpp"
#include "tls/memory_session.hpp"
#include "tls/server_credentials.hpp"

namespace unima::io {

namespace {

using asio::ip::tcp;

class TlsConnection final : public TcpSlaveServer::Connection {
 public:
  TlsConnection(TcpSlaveServer& server, tcp::socket socket, tls::HandshakeSlot handshake)
      : Connection(server, std::move(socket)),
        context_(server.options().tls->context),  // a renewal may replace the server's
        worker_(server.options().tls->handshake_worker),
        tls_(context_->native_handle()),
        handshake_slot_(std::move(handshake)) {
    cipher_in_.resize(record_room);
  }

  void start() override {
    last_activity_ = Clock::now();
    adu_started_ = Clock::now();
    idle_.watch();
    read_records();
  }

 private:
  void read() override { read_records(); }
  bool seal() override {
    if (!tls_.write(std::span(out_.data(), out_used_))) {
      finish("TLS: " + tls_.error());
      return false;
    }
    tls_.take_output(cipher_out_);  // the answers' records, sent like plain answers
    return true;
  }
  std::span<const std::uint8_t> outgoing() const override { return cipher_out_; }
  void sent_all() override {
    out_used_ = 0;
    cipher_out_.clear();
  }
  bool handshake_pending() const override { return !handshaken_; }
  bool waiting_for_worker() const override { return step_out_; }

  // RFC 8446 §6.1: a clean close is announced, so the client can tell it from a cut
  // connection. Best effort and never blocking: the alert goes only if the socket takes
  // it at once, and not while answers are still on their way (it would land inside them).
  void say_goodbye() override {
    if (step_out_ || peer_gone_ || !socket_.is_open() || !cipher_out_.empty() || !tls_.close_notify()) return;
    tls_.take_output(cipher_out_);
    boost::system::error_code ignored;
    socket_.write_some(asio::buffer(cipher_out_), ignored);
    cipher_out_.clear();
  }

  // Over TLS the socket is read like a plain one, into cipher_in_, and the records go
  // through the session in memory (tls/memory_session): the same system calls as plain
  // Modbus/TCP, and no asynchronous operation of an SSL stream around each.
  void read_records() {
    if (plaintext_waits_) return take_plaintext();  // in_ was full before the session was read to its end
    socket_.async_read_some(asio::buffer(cipher_in_), [this, self = shared_from_this()](const boost::system::error_code& ec, std::size_t n) {
      if (finished_) return;  // abandoned by a stopped port, whose worker may be gone
      if (ec) {
        peer_gone_ = true;  // nobody left to read a close_notify
        return finish(ec == asio::error::eof ? "closed by the client" : ec.message());
      }
      tls_.feed(std::span(cipher_in_.data(), n));
      if (!tls_.handshaken()) return handshake_step();
      take_plaintext();
    });
  }

  void take_plaintext() {
    if (pull_plaintext()) serve();
  }

  // The session's plaintext into in_, as far as it has room; false when the connection
  // finished (the client's close_notify, a broken record).
  bool pull_plaintext() {
    plaintext_waits_ = true;
    while (in_used_ < in_.size()) {
      std::size_t n = 0;
      const auto status = tls_.read(std::span(in_.data() + in_used_, in_.size() - in_used_), n);
      if (status == tls::MemorySession::Status::closed) {
        finish("closed by the client (close_notify)");
        return false;
      }
      if (status == tls::MemorySession::Status::failed) {
        // A record that does not authenticate is an attack or a broken path: the operator hears of it.
        send_alert();
        platform::warn_from_peer("modbus tls: broken sessions", peer_, "modbus tls: {} broke the session: {}; closing its connection",
                                 peer_, tls_.error());
        finish("TLS: " + tls_.error());
        return false;
      }
      if (status == tls::MemorySession::Status::want_input) {
        plaintext_waits_ = false;
        break;
      }
      in_used_ += n;
    }
    return true;
  }

  // While a request is forwarded: the records that came go through the session, so that
  // a close_notify is seen as the plain port sees an end of stream.
  void take_while_forwarding() override {
    boost::system::error_code ec;
    const auto n = socket_.read_some(asio::buffer(cipher_in_), ec);
    if (ec == asio::error::would_block || ec == asio::error::try_again) return watch_while_forwarding();
    if (ec) {
      peer_gone_ = true;
      return finish(ec == asio::error::eof ? "closed by the client" : ec.message());
    }
    tls_.feed(std::span(cipher_in_.data(), n));
    if (pull_plaintext() && !plaintext_waits_) watch_while_forwarding();
  }

  // Sends what the session wrote besides answers (its handshake flight), then reads on.
  void flush_records_then_read() {
    tls_.take_output(cipher_out_);
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
    tls_.take_output(cipher_out_);
    boost::system::error_code ignored;
    if (!cipher_out_.empty()) socket_.write_some(asio::buffer(cipher_out_), ignored);
  }

  // The step on the worker; the loop goes on with other clients meanwhile.
  void handshake_step() {
    const auto worker = worker_.lock();
    const auto handed_over = Clock::now();
    step_out_ = worker && worker->submit([session = &tls_, status = &step_status_] { *status = session->handshake(); },
                                         [this, self = shared_from_this(), handed_over] {
                                           step_out_ = false;
                                           resume_deadline(Clock::now() - handed_over);
                                           if (finished_) return;
                                           // Closed meanwhile without finishing (close() alone, as a stopped port does).
                                           if (!socket_.is_open()) return finish("closed while its handshake was computed");
                                           handshake_stepped(step_status_);
                                         });
    // Only when the port is gone: the worker takes as many steps as the limiter lets
    // handshakes be in progress, and each has at most one step out.
    if (!step_out_) finish("TLS: no room to compute the handshake");
  }

  // The time the step was out is not the client's: its deadline moves on by as much.
  void resume_deadline(Clock::duration out) {
    if (adu_started_) *adu_started_ += out;
    last_activity_ += out;
    if (socket_.is_open()) idle_.watch();
  }

  void handshake_stepped(tls::MemorySession::Status status) {
    if (status == tls::MemorySession::Status::failed || status == tls::MemorySession::Status::closed) {
      send_alert();
      const auto why = status == tls::MemorySession::Status::closed ? std::string("closed") : tls_.error();
      platform::warn_from_peer("modbus tls: failed handshakes", peer_, "modbus tls: {} failed the TLS handshake: {}", peer_, why);
      return finish("failed the TLS handshake");
    }
    if (status == tls::MemorySession::Status::want_input) return flush_records_then_read();
    handshake_slot_.completed();
    const auto identity = tls::client_identity(tls_.native_handle());
    role_ = identity.role;
    spdlog::debug("modbus tls: {} connected as {} (role {}), {}", peer_, platform::log_safe(identity.subject),
                  role_ ? platform::log_safe(*role_) : "none", SSL_get_version(tls_.native_handle()));
    // The monitor's port field and the log name the client: its role, or its certificate's
    // subject — the client's text, escaped.
    peer_ = platform::log_safe(role_ ? *role_ : identity.subject) + "@" + peer_;
    handshaken_ = true;
    adu_started_.reset();
    last_activity_ = Clock::now();
    plaintext_waits_ = true;  // a request may have come with the client's Finished
    flush_records_then_read();
  }


  std::shared_ptr<asio::ssl::context> context_;  // outlives tls_
  // Not owned: a connection may outlive its port, and the worker's completions hold connections.
  std::weak_ptr<CpuWorker> worker_;
  tls::MemorySession tls_;
  // A handshake step is on the worker: tls_ is the worker's until its completion runs.
  bool step_out_ = false;
  tls::MemorySession::Status step_status_ = tls::MemorySession::Status::want_input;  // the worker's answer
  // A TLS record holds at most 16 KiB of plaintext and some bytes of its own; the socket
  // is read in such pieces.
  static constexpr std::size_t record_room = 16 * 1024 + 512;
  std::vector<std::uint8_t> cipher_in_;
  std::vector<std::uint8_t> cipher_out_;  // records waiting for the socket
  bool plaintext_waits_ = false;          // the session may hold more than in_ took
  bool handshaken_ = false;
  bool peer_gone_ = false;  // its socket failed or reached its end
  tls::HandshakeSlot handshake_slot_;  // until the handshake completes; else its end counts it failed
};

}  // namespace

std::shared_ptr<TcpSlaveServer::Connection> make_tls_connection(TcpSlaveServer& server, tcp::socket socket,
                                                                tls::HandshakeSlot handshake) {
  return std::make_shared<TlsConnection>(server, std::move(socket), std::move(handshake));
}

}  // namespace unima::io
