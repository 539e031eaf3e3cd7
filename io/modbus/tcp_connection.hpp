#pragma once
// One client of the Modbus TCP slave (TcpSlaveServer): requests cut from the bytes it
// sent, answered in order, the answers to one read sent in one write, a write answered
// once durable (or refused, exception 04) with the requests behind it waiting for it, the
// idle and frame deadlines. Its bytes are the socket's own on a plain
// port; on a Modbus/TCP Security port TlsConnection (tls_connection.cpp) puts the records
// between the socket and this, and this never looks into a record.

#include <array>
#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "io/lazy_deadline.hpp"
#include "io/modbus/tcp_slave_server.hpp"
#include "modbus/mbap.hpp"
#include "modbus/slave_session.hpp"
#include "modbus/transaction.hpp"

namespace unima::io {

class TcpSlaveServer::Connection : public std::enable_shared_from_this<Connection> {
 public:
  using Clock = std::chrono::steady_clock;

  Connection(TcpSlaveServer& server, asio::ip::tcp::socket socket);
  virtual ~Connection() = default;

  virtual void start();
  void close();
  // The server stops and may be gone before this connection's pending handlers run
  // (aborted reads, a deferred read start): they must not call back into it.
  void abandon() {
    finished_ = true;
    close();
  }

  const std::string& peer() const { return peer_; }
  Clock::time_point last_activity() const { return last_activity_; }
  const asio::ip::address& address() const { return address_; }
  /// Closed by the server (for a new client, SPEC §10); the server logs why.
  void evict(const std::string& why) { finish(why); }

 protected:
  /// Reads what the client sent into in_, then serve().
  virtual void read();
  /// Makes out_'s answers ready for the socket; false (and finished) when it cannot.
  virtual bool seal() { return true; }
  /// What goes to the socket: the answers as they are (a TLS connection: their records).
  virtual std::span<const std::uint8_t> outgoing() const { return {out_.data(), out_used_}; }
  virtual void sent_all() { out_used_ = 0; }
  /// True while a TLS client has not finished its handshake (its deadline says so).
  virtual bool handshake_pending() const { return false; }
  /// True while the connection waits for the daemon's own work (a TLS handshake step on
  /// the worker): no deadline runs then, since the client is not the one who is late.
  virtual bool waiting_for_worker() const { return false; }
  /// What a protocol says before its connection closes (TLS: close_notify); nothing for plain TCP.
  virtual void say_goodbye() {}
  /// The socket is readable while a forwarded request waits: what the client sent is kept
  /// in in_ for after the answer, and a client that went is finished. Then watches again.
  virtual void take_while_forwarding();
  /// While a forwarded request waits for the line and its answer, nothing else reads the
  /// socket: this watches it, so that a client that goes is seen then and its queued
  /// request leaves the line's queue (SPEC §14) instead of going on the line for nobody.
  void watch_while_forwarding();
  modbus::PortKind port_kind() const { return server_.options_.tls ? modbus::PortKind::tls : modbus::PortKind::tcp; }

  /// Answers what in_ holds: at once, or once the state file holds what it wrote.
  void serve();
  void finish(const std::string& why);

  TcpSlaveServer& server_;
  asio::ip::tcp::socket socket_;
  std::string peer_;
  std::optional<std::string> role_;  // a TLS client's, from its certificate
  LazyDeadline idle_;
  // A full ADU is at most 260 bytes; room for several pipelined ones per read. Left
  // uninitialised: only the in_used_ bytes a read filled are ever looked at, and a client
  // that sends little then keeps only the pages it touched resident (issue #8's RSS).
  std::array<std::uint8_t, 4096> in_;
  std::size_t in_used_ = 0;
  std::vector<std::uint8_t> out_;  // out_used_ bytes of answers, then spare room
  std::size_t out_used_ = 0;
  Clock::time_point last_activity_;
  std::optional<Clock::time_point> adu_started_;  // when the first bytes of an incomplete request came
  bool finished_ = false;

 private:
  bool process();
  void note_progress(bool served);
  void send_once_durable();
  void answer_waiting_write(bool durable);
  void send();
  void read_more();
  void send_rest(std::size_t done);
  std::optional<Clock::time_point> idle_deadline() const;
  void close_idle();
  void finish_broken_stream();

  asio::ip::address address_;
  // The write whose answer ends out_ and waits for the state file (SPEC §10). The requests
  // behind it wait in in_, unserved, so that they see what it wrote; its answer becomes
  // exception 04 when the file refuses it, and the monitor sees the answer that is sent.
  struct WaitingWrite {
    std::uint64_t kept_as = 0;
    std::size_t answer_at = 0;  // where its answer's ADU begins in out_
    modbus::MbapHeader header;
    modbus::Served served;
    std::array<std::uint8_t, modbus::max_tcp_adu_size> request;
    std::size_t request_size = 0;
  };
  std::optional<WaitingWrite> waiting_;

  // A request for a foreign slave on the master's line (modbus.gateway, SPEC §14): like a
  // write waiting for the state file, its answer comes later and the requests behind it
  // wait in in_, so that the answers keep their order.
  struct Forwarding {
    modbus::MbapHeader header;
    std::array<std::uint8_t, modbus::max_tcp_adu_size> request;
    std::size_t request_size = 0;
  };
  std::optional<Forwarding> forwarding_;
  std::uint64_t client_id_;  // this connection's turn in the gateway's round
  std::uint64_t forwarded_count_ = 0;  // which forwarded request a watch of the socket belongs to
  const std::array<bool, 256>* routed_units() const;
  void forward();
  void answer_forwarded(std::span<const std::uint8_t> pdu);
};

/// A client of a Modbus/TCP Security port (tls_connection.cpp).
/// `handshake`: the place its handshake was given (TcpSlaveServer::admit_handshake).
std::shared_ptr<TcpSlaveServer::Connection> make_tls_connection(TcpSlaveServer& server, asio::ip::tcp::socket socket,
                                                                tls::HandshakeSlot handshake);

}  // namespace unima::io
