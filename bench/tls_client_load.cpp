// Load for Modbus/TCP Security (issue 18, docs/performance.md): the same client over plain
// TCP or TLS, so that the daemon's TLS figures are a ratio of its plain ones measured by
// one client. One thread, Asio; every loop bounded by --duration.
//
//   unima-bench-tls-load --port N [--tls CA CERT KEY] [--tls-version 1.2|1.3]
//                        [--mode requests|handshakes|flood] [--connections 8] [--duration 3]
//                        [--address 4352] [--quantity 64] [--hosts 1] [--source 127.0.0.2]
//                        [--attempts 0] [--rate 0]
//
// requests:   each connection sends FC4 × quantity, one request in flight, and checks the
//             answer; prints {"rps":…,"p50_us":…,"p99_us":…,"client_cpu_us":…} (the
//             client's own CPU time per request).
// handshakes: each connection loops connect → full handshake (no session resumption) →
//             one FC4 → close; prints {"handshakes_per_s":…,"p50_ms":…,"p99_ms":…}.
// flood:      issue 29 row 3's attacker: each connection loops connect from --source →
//             the same ClientHello, replayed → the server's first bytes or its close →
//             close, until --duration or --attempts connections in all, at most --rate
//             connections a second in all (0: as fast as they go); prints
//             {"attempts":…,"answered":…,"refused":…,"per_s":…}.
//
// --hosts N: the connections come from N source addresses, 127.1.0.0 on (Linux routes all
// of 127/8 on lo), each new connection from the next: the daemon limits handshakes per
// host (tls/handshake_limiter), which a benchmark of 64 connections or of handshakes per
// second from one address would measure instead of the port.

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <optional>
#include <span>
#include <string_view>
#include <stdexcept>
#include <string>
#include <vector>

#include <openssl/ssl.h>
#include <sys/resource.h>

#include "platform/asio.hpp"

namespace {

using namespace unima;
using asio::ip::tcp;
using Clock = std::chrono::steady_clock;

struct Options {
  std::uint16_t port = 0;
  std::optional<std::array<std::string, 3>> tls;  // CA, certificate, key
  enum class Mode { requests, handshakes, flood } mode = Mode::requests;
  int connections = 8;
  double duration = 3;
  std::uint16_t address = 4352;
  std::uint16_t quantity = 64;
  int tls_version = 0;   // --tls-version: the highest the client offers; 0: OpenSSL's default (1.3)
  int hosts = 1;         // source addresses; 1: 127.0.0.1, the kernel's choice
  std::string source;    // flood: the one source address
  std::uint64_t attempts = 0;  // flood: at most this many connections (0: no limit but the time)
  double rate = 0;             // flood: at most this many connections a second (0: no limit)
};

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const auto next = [&] {
      if (i + 1 >= argc) throw std::runtime_error(a + " needs a value");
      return std::string(argv[++i]);
    };
    if (a == "--port") o.port = static_cast<std::uint16_t>(std::stoi(next()));
    else if (a == "--tls") o.tls = std::array{next(), next(), next()};
    else if (a == "--mode") {
      const auto mode = next();
      o.mode = mode == "handshakes" ? Options::Mode::handshakes : mode == "flood" ? Options::Mode::flood : Options::Mode::requests;
    }
    else if (a == "--connections") o.connections = std::stoi(next());
    else if (a == "--duration") o.duration = std::stod(next());
    else if (a == "--address") o.address = static_cast<std::uint16_t>(std::stoi(next()));
    else if (a == "--quantity") o.quantity = static_cast<std::uint16_t>(std::stoi(next()));
    else if (a == "--tls-version") o.tls_version = next() == "1.2" ? TLS1_2_VERSION : TLS1_3_VERSION;
    else if (a == "--hosts") o.hosts = std::max(1, std::stoi(next()));
    else if (a == "--source") o.source = next();
    else if (a == "--attempts") o.attempts = std::stoull(next());
    else if (a == "--rate") o.rate = std::stod(next());
    else throw std::runtime_error("unknown option " + a);
  }
  if (o.port == 0) throw std::runtime_error("--port is required");
  return o;
}

// A client's TLS session on OpenSSL over memory: the socket is written and read as in plain
// TCP and OpenSSL's own record layer works on the bytes, as the daemon's does (an
// independent peer nonetheless: the daemon's code around OpenSSL is not the client's).
// Asio's SSL stream, which this client used before, cost it more CPU per request than the
// daemon; on a machine whose cores both share, that held the daemon's TLS figures down
// (docs/performance.md).
class ClientSession {
 public:
  explicit ClientSession(SSL_CTX* context) : ssl_(SSL_new(context)) {
    if (ssl_ == nullptr) throw std::runtime_error("OpenSSL cannot make a session");
    in_ = BIO_new(BIO_s_mem());
    out_ = BIO_new(BIO_s_mem());
    BIO_set_mem_eof_return(in_, -1);
    SSL_set_bio(ssl_, in_, out_);
    SSL_set_connect_state(ssl_);
  }
  ~ClientSession() { SSL_free(ssl_); }
  ClientSession(const ClientSession&) = delete;
  ClientSession& operator=(const ClientSession&) = delete;

  enum class Step : std::uint8_t { done, want_input, failed };

  void feed(const std::uint8_t* data, std::size_t size) { BIO_write(in_, data, static_cast<int>(size)); }
  Step handshake() { return step(SSL_do_handshake(ssl_)); }
  bool write(std::span<const std::uint8_t> plaintext) {
    return SSL_write(ssl_, plaintext.data(), static_cast<int>(plaintext.size())) == static_cast<int>(plaintext.size());
  }
  Step read(std::span<std::uint8_t> out, std::size_t& n) {
    const int result = SSL_read(ssl_, out.data(), static_cast<int>(out.size()));
    n = result > 0 ? static_cast<std::size_t>(result) : 0;
    return result > 0 ? Step::done : step(result);
  }
  void take_output(std::vector<std::uint8_t>& out) {
    out.resize(static_cast<std::size_t>(BIO_ctrl_pending(out_)));
    if (!out.empty()) BIO_read(out_, out.data(), static_cast<int>(out.size()));
  }

 private:
  Step step(int result) {
    if (result == 1) return Step::done;
    const int error = SSL_get_error(ssl_, result);
    return error == SSL_ERROR_WANT_READ || error == SSL_ERROR_WANT_WRITE ? Step::want_input : Step::failed;
  }
  SSL* ssl_;
  BIO* in_;
  BIO* out_;
};

// The source address of a new connection: the next of --hosts, or none (the kernel's).
std::optional<asio::ip::address_v4> next_source(const Options& o, std::uint64_t& counter) {
  if (!o.source.empty()) return asio::ip::make_address_v4(o.source);
  if (o.hosts <= 1) return std::nullopt;
  const auto index = static_cast<std::uint32_t>(counter++ % static_cast<std::uint64_t>(o.hosts));
  return asio::ip::address_v4((127U << 24) | (1U << 16) | index);
}

// One client connection, plain or TLS.
class Client : public std::enable_shared_from_this<Client> {
 public:
  struct Shared {
    const Options& options;
    SSL_CTX* tls;
    Clock::time_point start;
    Clock::time_point until;
    std::vector<double> latencies;  // µs per request, or ms per handshake
    std::uint64_t done = 0;
    std::string error;
    std::uint64_t sources = 0;   // connections given a source address so far
    std::uint64_t scheduled = 0;  // flood: connections given their time
    std::uint64_t attempts = 0;  // flood
    std::uint64_t answered = 0;  // flood: the server's first flight came
    std::vector<std::uint8_t> client_hello;  // flood: the one replayed
  };

  Client(asio::io_context& io, Shared& shared) : io_(io), shared_(shared), pacing_(io) {
    const auto& o = shared.options;
    request_ = {0, 0, 0, 0, 0, 6, 1, 4, static_cast<std::uint8_t>(o.address >> 8), static_cast<std::uint8_t>(o.address),
                static_cast<std::uint8_t>(o.quantity >> 8), static_cast<std::uint8_t>(o.quantity)};
    answer_.resize(9 + 2 * std::size_t{o.quantity});
    cipher_in_.resize(16 * 1024 + 512);
  }

  void start() { connect(); }

 private:
  void connect() {
    const auto& o = shared_.options;
    if (Clock::now() >= shared_.until) return;
    if (o.mode == Options::Mode::flood) {
      if (o.attempts != 0 && shared_.scheduled >= o.attempts) return;
      // Paced: the n-th connection not before start + n / rate.
      const auto due = shared_.start + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(
                                           o.rate > 0 ? static_cast<double>(shared_.scheduled) / o.rate : 0.0));
      ++shared_.scheduled;
      if (Clock::now() < due) {
        pacing_.expires_at(due);
        return pacing_.async_wait([this, self = shared_from_this()](const boost::system::error_code&) { connect_now(); });
      }
    }
    connect_now();
  }

  void connect_now() {
    const auto& o = shared_.options;
    if (Clock::now() >= shared_.until) return;
    socket_.emplace(io_);
    if (const auto source = next_source(o, shared_.sources)) {
      socket_->open(tcp::v4());
      socket_->bind(tcp::endpoint(*source, 0));
    }
    if (shared_.tls && o.mode != Options::Mode::flood) session_.emplace(shared_.tls);
    connected_at_ = Clock::now();
    socket_->async_connect(tcp::endpoint(asio::ip::address_v4::loopback(), o.port),
                           [this, self = shared_from_this()](const boost::system::error_code& ec) {
                             if (ec) return fail("connect: " + ec.message());
                             socket_->set_option(tcp::no_delay(true));
                             if (shared_.options.mode == Options::Mode::flood) return replay_client_hello();
                             if (!session_) return send();
                             handshake();
                           });
  }

  // The attacker's loop: what the server does with the replayed ClientHello is all it
  // wants; refused at accept, the connection just ends.
  void replay_client_hello() {
    ++shared_.attempts;
    asio::async_write(*socket_, asio::buffer(shared_.client_hello), [this, self = shared_from_this()](
                                                                        const boost::system::error_code& ec, std::size_t) {
      if (ec) return next_attempt(false);
      socket_->async_read_some(asio::buffer(cipher_in_), [this, self](const boost::system::error_code& e, std::size_t n) {
        next_attempt(!e && n > 0);
      });
    });
  }
  void next_attempt(bool answered) {
    if (answered) ++shared_.answered;
    boost::system::error_code ignored;
    // Reset, not closed: no TIME_WAIT left behind, whose thousands of ports would slow this
    // host's next connects (an attacker would not wait for them either).
    socket_->set_option(asio::socket_base::linger(true, 0), ignored);
    socket_->close(ignored);
    connect();
  }

  // The client's Finished goes out with the first request.
  void handshake() {
    const auto step = session_->handshake();
    if (step == ClientSession::Step::failed) return fail("handshake failed");
    if (step == ClientSession::Step::done) return send();
    session_->take_output(cipher_out_);
    const auto read_on = [this, self = shared_from_this()] {
      socket_->async_read_some(asio::buffer(cipher_in_), [this, self](const boost::system::error_code& ec, std::size_t n) {
        if (ec) return fail("handshake: " + ec.message());
        session_->feed(cipher_in_.data(), n);
        handshake();
      });
    };
    if (cipher_out_.empty()) return read_on();
    asio::async_write(*socket_, asio::buffer(cipher_out_), [this, read_on](const boost::system::error_code& ec, std::size_t) {
      if (ec) return fail("handshake: " + ec.message());
      read_on();
    });
  }

  void send() {
    ++transaction_;
    request_[0] = static_cast<std::uint8_t>(transaction_ >> 8);
    request_[1] = static_cast<std::uint8_t>(transaction_);
    sent_at_ = Clock::now();
    auto on_sent = [this, self = shared_from_this()](const boost::system::error_code& ec, std::size_t) {
      if (ec) return fail("write: " + ec.message());
      received_ = 0;
      receive();
    };
    if (!session_) return asio::async_write(*socket_, asio::buffer(request_), on_sent);
    if (!session_->write(request_)) return fail("TLS write failed");
    session_->take_output(cipher_out_);
    asio::async_write(*socket_, asio::buffer(cipher_out_), on_sent);
  }

  void receive() {
    if (!session_) {
      return asio::async_read(*socket_, asio::buffer(answer_),
                              [this, self = shared_from_this()](const boost::system::error_code& ec, std::size_t) {
                                if (ec) return fail("read: " + ec.message());
                                answered();
                              });
    }
    while (received_ < answer_.size()) {
      std::size_t n = 0;
      const auto step = session_->read(std::span(answer_).subspan(received_), n);
      if (step == ClientSession::Step::failed) return fail("TLS read failed");
      if (step == ClientSession::Step::want_input) {
        return socket_->async_read_some(asio::buffer(cipher_in_), [this, self = shared_from_this()](
                                                                      const boost::system::error_code& ec, std::size_t got) {
          if (ec) return fail("read: " + ec.message());
          session_->feed(cipher_in_.data(), got);
          receive();
        });
      }
      received_ += n;
    }
    answered();
  }

  void answered() {
    const auto& o = shared_.options;
    if (answer_[0] != request_[0] || answer_[1] != request_[1] || answer_[7] != 4 || answer_[8] != 2 * o.quantity)
      return fail("a wrong answer");
    const auto now = Clock::now();
    if (o.mode == Options::Mode::handshakes) {
      shared_.latencies.push_back(std::chrono::duration<double, std::milli>(now - connected_at_).count());
      ++shared_.done;
      boost::system::error_code ignored;
      socket_->close(ignored);
      session_.reset();
      return connect();
    }
    shared_.latencies.push_back(std::chrono::duration<double, std::micro>(now - sent_at_).count());
    ++shared_.done;
    if (now < shared_.until) send();
  }

  void fail(const std::string& why) {
    if (shared_.error.empty()) shared_.error = why;
    io_.stop();
  }

  asio::io_context& io_;
  Shared& shared_;
  asio::steady_timer pacing_;
  std::optional<tcp::socket> socket_;
  std::optional<ClientSession> session_;
  std::vector<std::uint8_t> request_;
  std::vector<std::uint8_t> answer_;
  std::size_t received_ = 0;
  std::vector<std::uint8_t> cipher_in_;
  std::vector<std::uint8_t> cipher_out_;
  std::uint16_t transaction_ = 0;
  Clock::time_point sent_at_, connected_at_;
};

double percentile(std::vector<double>& values, double p) {
  if (values.empty()) return 0;
  const auto at = static_cast<std::size_t>(p * static_cast<double>(values.size() - 1));
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(at), values.end());
  return values[at];
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const auto options = parse(argc, argv);
    asio::io_context io;
    std::unique_ptr<SSL_CTX, decltype(&SSL_CTX_free)> tls(nullptr, SSL_CTX_free);
    if (options.tls) {
      tls.reset(SSL_CTX_new(TLS_client_method()));
      const auto& [ca, certificate, key] = *options.tls;
      if (!tls || SSL_CTX_load_verify_locations(tls.get(), ca.c_str(), nullptr) != 1 ||
          SSL_CTX_use_certificate_chain_file(tls.get(), certificate.c_str()) != 1 ||
          SSL_CTX_use_PrivateKey_file(tls.get(), key.c_str(), SSL_FILETYPE_PEM) != 1)
        throw std::runtime_error("cannot load the client's certificate, key or CA");
      SSL_CTX_set_verify(tls.get(), SSL_VERIFY_PEER, nullptr);
      // Every handshake a full one.
      SSL_CTX_set_session_cache_mode(tls.get(), SSL_SESS_CACHE_OFF);
      SSL_CTX_set_options(tls.get(), SSL_OP_NO_TICKET);
      if (options.tls_version != 0) SSL_CTX_set_max_proto_version(tls.get(), options.tls_version);
    }
    const auto start = Clock::now();
    Client::Shared shared{options, tls.get(), start,
                          start + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(options.duration)),
                          {}, 0, {}, 0, 0, 0, 0, {}};
    if (options.mode == Options::Mode::flood) {
      // One ClientHello, made once and sent on every connection: what costs the attacker
      // nothing and the server a key pair and a signature each time.
      std::unique_ptr<SSL_CTX, decltype(&SSL_CTX_free)> hello_context(SSL_CTX_new(TLS_client_method()), SSL_CTX_free);
      ClientSession hello(hello_context.get());
      hello.handshake();
      hello.take_output(shared.client_hello);
      if (shared.client_hello.empty()) throw std::runtime_error("OpenSSL wrote no ClientHello");
    }
    for (int i = 0; i < options.connections; ++i) std::make_shared<Client>(io, shared)->start();
    io.run();
    if (!shared.error.empty()) {
      std::fprintf(stderr, "unima-bench-tls-load: %s\n", shared.error.c_str());
      return 1;
    }
    const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
    // The client's own CPU time: on a machine whose cores it shares with the daemon, what
    // TLS costs the client is taken from the daemon's throughput.
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    const double cpu_seconds = static_cast<double>(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
                               static_cast<double>(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec) / 1e6;
    const double cpu_us = shared.done > 0 ? cpu_seconds * 1e6 / static_cast<double>(shared.done) : 0;
    const double rate = static_cast<double>(shared.done) / seconds;
    const double p50 = percentile(shared.latencies, 0.5), p99 = percentile(shared.latencies, 0.99);
    if (options.mode == Options::Mode::flood)
      std::printf("{\"attempts\":%llu,\"answered\":%llu,\"refused\":%llu,\"per_s\":%.1f,\"connections\":%d}\n",
                  static_cast<unsigned long long>(shared.attempts), static_cast<unsigned long long>(shared.answered),
                  static_cast<unsigned long long>(shared.attempts - shared.answered),
                  static_cast<double>(shared.attempts) / seconds, options.connections);
    else if (options.mode == Options::Mode::handshakes)
      std::printf("{\"handshakes_per_s\":%.1f,\"p50_ms\":%.3f,\"p99_ms\":%.3f,\"connections\":%d,\"client_cpu_us\":%.2f}\n",
                  rate, p50, p99, options.connections, cpu_us);
    else
      std::printf("{\"rps\":%.1f,\"p50_us\":%.1f,\"p99_us\":%.1f,\"connections\":%d,\"tls\":%s,\"client_cpu_us\":%.2f}\n",
                  rate, p50, p99, options.connections, options.tls ? "true" : "false", cpu_us);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "unima-bench-tls-load: %s\n", e.what());
    return 1;
  }
}
