// Load for Modbus/TCP Security (issue 18, docs/performance.md): the same client over plain
// TCP or TLS, so that the daemon's TLS figures are a ratio of its plain ones measured by
// one client. One thread, Asio; every loop bounded by --duration.
//
//   unima-bench-tls-load --port N [--tls CA CERT KEY] [--records openssl|port]
//                        [--mode requests|handshakes] [--connections 8] [--duration 3]
//                        [--address 4352] [--quantity 64]
//
// requests:   each connection sends FC4 × quantity, one request in flight, and checks the
//             answer; prints {"rps":…,"p50_us":…,"p99_us":…,"client_cpu_us":…} (the
//             client's own CPU time per request).
// handshakes: each connection loops connect → full handshake (no session resumption) →
//             one FC4 → close; prints {"handshakes_per_s":…,"p50_ms":…,"p99_ms":…}.

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
#include "tls/key_log.hpp"
#include "tls/record_layer.hpp"

namespace {

using namespace unima;
using asio::ip::tcp;
using Clock = std::chrono::steady_clock;

struct Options {
  std::uint16_t port = 0;
  std::optional<std::array<std::string, 3>> tls;  // CA, certificate, key
  bool handshakes = false;
  int connections = 8;
  double duration = 3;
  std::uint16_t address = 4352;
  std::uint16_t quantity = 64;
  bool port_records = false;  // --records port
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
    else if (a == "--mode") o.handshakes = next() == "handshakes";
    else if (a == "--connections") o.connections = std::stoi(next());
    else if (a == "--duration") o.duration = std::stod(next());
    else if (a == "--address") o.address = static_cast<std::uint16_t>(std::stoi(next()));
    else if (a == "--quantity") o.quantity = static_cast<std::uint16_t>(std::stoi(next()));
    else if (a == "--records") o.port_records = next() == "port";
    else throw std::runtime_error("unknown option " + a);
  }
  if (o.port == 0) throw std::runtime_error("--port is required");
  return o;
}

// A client's TLS session on OpenSSL over memory: the socket is written and read as in plain
// TCP and OpenSSL's own record layer works on the bytes (an independent peer for the
// daemon's tls/record_layer). Asio's SSL stream, which this client used before, cost it
// more CPU per request than the daemon; on a machine whose cores both share, that held
// the daemon's TLS figures down (docs/performance.md).
//
// With --records port the records after a TLS 1.3 handshake go through the port's own
// tls::RecordLayer instead, mirrored (it receives under the server's secret): a client
// that costs less per request than the daemon, so that the daemon, not the client, is what
// the end-to-end figure measures on a machine where both share the cores.
class ClientSession {
 public:
  ClientSession(SSL_CTX* context, bool port_records) : ssl_(SSL_new(context)), port_records_(port_records) {
    if (ssl_ == nullptr) throw std::runtime_error("OpenSSL cannot make a session");
    in_ = BIO_new(BIO_s_mem());
    out_ = BIO_new(BIO_s_mem());
    BIO_set_mem_eof_return(in_, -1);
    SSL_set_bio(ssl_, in_, out_);
    SSL_set_connect_state(ssl_);
    SSL_set_ex_data(ssl_, secrets_index(), &secrets_);
  }
  ~ClientSession() { SSL_free(ssl_); }
  ClientSession(const ClientSession&) = delete;
  ClientSession& operator=(const ClientSession&) = delete;

  enum class Step : std::uint8_t { done, want_input, failed };

  // Keeps a handshake's two application traffic secrets (NSS key-log lines) for --records port.
  static void keep_secrets(const SSL* ssl, const char* line) {
    auto* secrets = static_cast<std::array<std::vector<std::uint8_t>, 2>*>(SSL_get_ex_data(ssl, secrets_index()));
    if (secrets == nullptr) return;
    if (!tls::read_key_log_secret(line, "CLIENT_TRAFFIC_SECRET_0", (*secrets)[0]))
      tls::read_key_log_secret(line, "SERVER_TRAFFIC_SECRET_0", (*secrets)[1]);
  }

  void feed(const std::uint8_t* data, std::size_t size) {
    if (records_) return records_->feed(std::span(data, size));
    BIO_write(in_, data, static_cast<int>(size));
  }
  Step handshake() {
    const auto result = step(SSL_do_handshake(ssl_));
    if (result == Step::done && port_records_) {
      if (SSL_version(ssl_) != TLS1_3_VERSION || secrets_[0].empty() || secrets_[1].empty()) return Step::failed;
      take_bio_output(finished_);
      records_.emplace(SSL_CIPHER_get_protocol_id(SSL_get_current_cipher(ssl_)), secrets_[1], secrets_[0]);
      std::vector<std::uint8_t> rest(static_cast<std::size_t>(BIO_ctrl_pending(in_)));
      if (!rest.empty()) BIO_read(in_, rest.data(), static_cast<int>(rest.size()));
      records_->feed(rest);
    }
    return result;
  }
  bool write(std::span<const std::uint8_t> plaintext) {
    if (records_) {
      records_->write(plaintext);
      return true;
    }
    return SSL_write(ssl_, plaintext.data(), static_cast<int>(plaintext.size())) == static_cast<int>(plaintext.size());
  }
  Step read(std::span<std::uint8_t> out, std::size_t& n) {
    if (records_) {
      const auto status = records_->read(out, n);
      return status == tls::RecordLayer::Status::done         ? Step::done
             : status == tls::RecordLayer::Status::want_input ? Step::want_input
                                                               : Step::failed;
    }
    const int result = SSL_read(ssl_, out.data(), static_cast<int>(out.size()));
    n = result > 0 ? static_cast<std::size_t>(result) : 0;
    return result > 0 ? Step::done : step(result);
  }
  void take_output(std::vector<std::uint8_t>& out) {
    out.clear();
    if (!records_) return take_bio_output(out);
    out.swap(finished_);
    records_->take_output(out);
  }

 private:
  static int secrets_index() {
    static const int index = SSL_get_ex_new_index(0, nullptr, nullptr, nullptr, nullptr);
    return index;
  }
  void take_bio_output(std::vector<std::uint8_t>& out) {
    out.resize(static_cast<std::size_t>(BIO_ctrl_pending(out_)));
    if (!out.empty()) BIO_read(out_, out.data(), static_cast<int>(out.size()));
  }
  Step step(int result) {
    if (result == 1) return Step::done;
    const int error = SSL_get_error(ssl_, result);
    return error == SSL_ERROR_WANT_READ || error == SSL_ERROR_WANT_WRITE ? Step::want_input : Step::failed;
  }
  SSL* ssl_;
  BIO* in_;
  BIO* out_;
  bool port_records_;
  std::array<std::vector<std::uint8_t>, 2> secrets_;  // the client's, the server's
  std::optional<tls::RecordLayer> records_;
  std::vector<std::uint8_t> finished_;  // the client's Finished, out with the first request
};

// One client connection, plain or TLS.
class Client : public std::enable_shared_from_this<Client> {
 public:
  struct Shared {
    const Options& options;
    SSL_CTX* tls;
    Clock::time_point until;
    std::vector<double> latencies;  // µs per request, or ms per handshake
    std::uint64_t done = 0;
    std::string error;
  };

  Client(asio::io_context& io, Shared& shared) : io_(io), shared_(shared) {
    const auto& o = shared.options;
    request_ = {0, 0, 0, 0, 0, 6, 1, 4, static_cast<std::uint8_t>(o.address >> 8), static_cast<std::uint8_t>(o.address),
                static_cast<std::uint8_t>(o.quantity >> 8), static_cast<std::uint8_t>(o.quantity)};
    answer_.resize(9 + 2 * std::size_t{o.quantity});
    cipher_in_.resize(16 * 1024 + 512);
  }

  void start() { connect(); }

 private:
  void connect() {
    if (Clock::now() >= shared_.until) return;
    socket_.emplace(io_);
    if (shared_.tls) session_.emplace(shared_.tls, shared_.options.port_records);
    connected_at_ = Clock::now();
    socket_->async_connect(tcp::endpoint(asio::ip::address_v4::loopback(), shared_.options.port),
                           [this, self = shared_from_this()](const boost::system::error_code& ec) {
                             if (ec) return fail("connect: " + ec.message());
                             socket_->set_option(tcp::no_delay(true));
                             if (!session_) return send();
                             handshake();
                           });
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
    if (o.handshakes) {
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
      if (options.port_records) SSL_CTX_set_keylog_callback(tls.get(), ClientSession::keep_secrets);
    }
    const auto start = Clock::now();
    Client::Shared shared{options, tls.get(),
                          start + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(options.duration)),
                          {}, 0, {}};
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
    if (options.handshakes)
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
