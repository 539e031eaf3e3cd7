// unima-bench-load: a Modbus TCP load generator on plain sockets and one epoll loop. Each
// connection keeps `depth` requests in flight (pipelining) and sends the replacements for
// the responses of one read in one send. Every response is checked (transaction id in
// order, protocol id, length, unit, function, byte count or echo); the first bad one ends
// the run with exit code 1. Prints requests/s and the latency percentiles.

#include <sys/epoll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

#include "bench/bench_util.hpp"

namespace unima::bench {
namespace {

constexpr const char* usage =
    "usage: unima-bench-load --port N [--host 127.0.0.1] [--connections 1] [--depth 1]\n"
    "         [--function 4] [--address 0] [--quantity 1] [--value 0] [--unit 1]\n"
    "         [--duration 2] [--warmup 0] [--requests 0] [--timeout 5] [--json]\n"
    "  --duration S  seconds to issue requests after the warm-up (0: bounded by --requests only)\n"
    "  --requests N  issue exactly N requests in all (0: bounded by --duration only)\n"
    "  --function    3 or 4 (read --quantity registers), 6 (write --value), 16 (write --quantity x --value)\n";

struct Plan {
  std::uint8_t function = 4;
  std::uint8_t unit = 1;
  std::vector<std::uint8_t> request;  // one ADU; the transaction id is patched per request
  std::size_t response_size = 0;
};

void put16(std::vector<std::uint8_t>& bytes, std::uint16_t value) {
  bytes.push_back(static_cast<std::uint8_t>(value >> 8));
  bytes.push_back(static_cast<std::uint8_t>(value));
}
std::uint16_t get16(const std::uint8_t* bytes) { return static_cast<std::uint16_t>(bytes[0] << 8 | bytes[1]); }

Plan make_plan(const Args& args) {
  Plan plan;
  plan.function = static_cast<std::uint8_t>(args.number("function"));
  plan.unit = static_cast<std::uint8_t>(args.number("unit"));
  const auto address = static_cast<std::uint16_t>(args.number("address"));
  const auto quantity = static_cast<std::uint16_t>(args.number("quantity"));
  const auto value = static_cast<std::uint16_t>(args.number("value"));
  std::vector<std::uint8_t> pdu{plan.function};
  put16(pdu, address);
  switch (plan.function) {
    case 3:
    case 4:
      if (quantity < 1 || quantity > 125) throw std::runtime_error("--quantity must be 1..125 for a read");
      put16(pdu, quantity);
      plan.response_size = 9 + 2 * std::size_t{quantity};
      break;
    case 6:
      put16(pdu, value);
      plan.response_size = 12;
      break;
    case 16:
      if (quantity < 1 || quantity > 123) throw std::runtime_error("--quantity must be 1..123 for function 16");
      put16(pdu, quantity);
      pdu.push_back(static_cast<std::uint8_t>(2 * quantity));
      for (unsigned i = 0; i < quantity; ++i) put16(pdu, value);
      plan.response_size = 12;
      break;
    default: throw std::runtime_error("--function must be 3, 4, 6 or 16");
  }
  plan.request = {0, 0, 0, 0};
  put16(plan.request, static_cast<std::uint16_t>(pdu.size() + 1));
  plan.request.push_back(plan.unit);
  plan.request.insert(plan.request.end(), pdu.begin(), pdu.end());
  return plan;
}

// Why a response is not the one expected, or empty when it is.
std::string check_response(const Plan& plan, const std::uint8_t* r, std::size_t size, std::uint16_t transaction) {
  if (get16(r) != transaction)
    return "transaction id " + std::to_string(get16(r)) + ", expected " + std::to_string(transaction);
  if (get16(r + 2) != 0) return "protocol id " + std::to_string(get16(r + 2));
  if (r[6] != plan.unit) return "unit id " + std::to_string(r[6]);
  if (r[7] == (plan.function | 0x80) && size == 9) return "exception " + std::to_string(r[8]);
  if (r[7] != plan.function) return "function " + std::to_string(r[7]);
  if (size != plan.response_size) return "response of " + std::to_string(size) + " bytes";
  if (plan.function == 3 || plan.function == 4) {
    if (r[8] != plan.response_size - 9) return "byte count " + std::to_string(r[8]);
  } else if (!std::equal(r + 7, r + 12, plan.request.begin() + 7)) {
    return "the echo differs from the request";
  }
  return {};
}

struct Connection {
  int fd = -1;
  std::uint64_t sent = 0;
  std::uint64_t received = 0;
  std::vector<std::uint64_t> sent_at;  // by request number modulo depth
  std::vector<std::uint8_t> in;
  std::size_t in_used = 0;
};

class LoadGenerator {
 public:
  explicit LoadGenerator(const Args& args)
      : plan_(make_plan(args)),
        connections_(args.number("connections")),
        depth_(args.number("depth")),
        budget_(args.number("requests")),
        timeout_ns_(static_cast<std::uint64_t>(args.real("timeout") * 1e9)) {
    if (connections_.empty()) throw std::runtime_error("--connections must be at least 1");
    if (depth_ < 1 || depth_ > 1000) throw std::runtime_error("--depth must be 1..1000");
    const double duration = args.real("duration");
    if (duration == 0 && budget_ == 0) throw std::runtime_error("give --duration or --requests");
    epoll_ = ::epoll_create1(EPOLL_CLOEXEC);
    for (std::size_t i = 0; i < connections_.size(); ++i) {
      auto& c = connections_[i];
      c.fd = connect_tcp(args.text("host"), static_cast<std::uint16_t>(args.number("port")));
      c.sent_at.resize(depth_);
      c.in.resize(depth_ * std::max<std::size_t>(plan_.response_size, 9) + 512);
      epoll_event ev{};
      ev.events = EPOLLIN;
      ev.data.u64 = i;
      if (::epoll_ctl(epoll_, EPOLL_CTL_ADD, c.fd, &ev) != 0) throw std::runtime_error("epoll_ctl");
    }
    const auto start = now_ns();
    measure_from_ = start + static_cast<std::uint64_t>(args.real("warmup") * 1e9);
    issue_until_ = duration > 0 ? measure_from_ + static_cast<std::uint64_t>(duration * 1e9) : UINT64_MAX;
    out_.reserve(depth_ * plan_.request.size());
    latencies_.reserve(1 << 20);
  }

  ~LoadGenerator() {
    for (auto& c : connections_)
      if (c.fd >= 0) ::close(c.fd);
    if (epoll_ >= 0) ::close(epoll_);
  }

  void run() {
    for (auto& c : connections_) issue(c, depth_, now_ns());
    std::vector<epoll_event> events(connections_.size());
    auto last_progress = now_ns();
    while (in_flight_ > 0) {
      const int n = ::epoll_wait(epoll_, events.data(), static_cast<int>(events.size()), 100);
      if (n < 0 && errno == EINTR) continue;
      if (n < 0) throw std::runtime_error(std::string("epoll_wait: ") + std::strerror(errno));
      if (n == 0) {
        if (now_ns() - last_progress > timeout_ns_)
          throw std::runtime_error(std::to_string(in_flight_) + " requests unanswered after the time-out");
        continue;
      }
      for (int i = 0; i < n; ++i) take(connections_[events[static_cast<std::size_t>(i)].data.u64]);
      last_progress = now_ns();
    }
  }

  void report(bool json) {
    const double seconds = measured_ == 0 ? 0 : static_cast<double>(last_measured_at_ - measure_from_) / 1e9;
    const double rps = seconds > 0 ? static_cast<double>(measured_) / seconds : 0;
    const auto p = percentiles(latencies_);
    if (json) {
      std::printf("{\"requests\":%llu,\"total\":%llu,\"seconds\":%.6f,\"rps\":%.1f,\"p50_us\":%.2f,\"p99_us\":%.2f,"
                  "\"p999_us\":%.2f,\"max_us\":%.2f,\"connections\":%zu,\"depth\":%zu}\n",
                  static_cast<unsigned long long>(measured_), static_cast<unsigned long long>(issued_), seconds, rps,
                  p.p50, p.p99, p.p999, p.max, connections_.size(), depth_);
    } else {
      std::printf("%zu connections, depth %zu: %llu requests in %.3f s = %.0f requests/s\n"
                  "latency: p50 %.1f us  p99 %.1f us  p99.9 %.1f us  max %.1f us\n",
                  connections_.size(), depth_, static_cast<unsigned long long>(measured_), seconds, rps, p.p50,
                  p.p99, p.p999, p.max);
    }
  }

 private:
  // Sends up to `count` requests on `c` in one send, within the time and count bounds.
  void issue(Connection& c, std::size_t count, std::uint64_t now) {
    if (now >= issue_until_) return;
    if (budget_ > 0) count = std::min<std::uint64_t>(count, budget_ - issued_);
    if (count == 0) return;
    out_.clear();
    for (std::size_t i = 0; i < count; ++i) {
      const auto transaction = static_cast<std::uint16_t>(c.sent);
      out_.insert(out_.end(), plan_.request.begin(), plan_.request.end());
      out_[out_.size() - plan_.request.size()] = static_cast<std::uint8_t>(transaction >> 8);
      out_[out_.size() - plan_.request.size() + 1] = static_cast<std::uint8_t>(transaction);
      c.sent_at[c.sent % depth_] = now;
      ++c.sent;
    }
    send_all(c.fd, out_);
    issued_ += count;
    in_flight_ += count;
  }

  void take(Connection& c) {
    const auto n = ::recv(c.fd, c.in.data() + c.in_used, c.in.size() - c.in_used, MSG_DONTWAIT);
    if (n < 0 && (errno == EAGAIN || errno == EINTR)) return;
    if (n < 0) throw std::runtime_error(std::string("recv: ") + std::strerror(errno));
    if (n == 0) throw std::runtime_error("the server closed a connection");
    c.in_used += static_cast<std::size_t>(n);
    const auto now = now_ns();
    std::size_t at = 0;
    std::size_t answered = 0;
    while (c.in_used - at >= 7) {
      const std::size_t size = 6 + std::size_t{get16(c.in.data() + at + 4)};
      if (size < 8 || size > 260) throw std::runtime_error("response with MBAP length " + std::to_string(size - 6));
      if (c.in_used - at < size) break;
      if (c.received == c.sent) throw std::runtime_error("a response to no request");
      const auto why = check_response(plan_, c.in.data() + at, size, static_cast<std::uint16_t>(c.received));
      if (!why.empty()) throw std::runtime_error("bad response: " + why);
      const auto sent_at = c.sent_at[c.received % depth_];
      if (sent_at >= measure_from_) {
        latencies_.push_back(static_cast<std::uint32_t>(std::min<std::uint64_t>(now - sent_at, UINT32_MAX)));
        ++measured_;
        last_measured_at_ = now;
      }
      ++c.received;
      ++answered;
      at += size;
    }
    if (at > 0) {
      std::memmove(c.in.data(), c.in.data() + at, c.in_used - at);
      c.in_used -= at;
    }
    in_flight_ -= answered;
    issue(c, answered, now);
  }

  Plan plan_;
  std::vector<Connection> connections_;
  std::size_t depth_;
  std::uint64_t budget_;
  std::uint64_t timeout_ns_;
  int epoll_ = -1;
  std::uint64_t measure_from_ = 0;
  std::uint64_t issue_until_ = 0;
  std::uint64_t issued_ = 0;
  std::uint64_t in_flight_ = 0;
  std::uint64_t measured_ = 0;
  std::uint64_t last_measured_at_ = 0;
  std::vector<std::uint8_t> out_;
  std::vector<std::uint32_t> latencies_;
};

}  // namespace
}  // namespace unima::bench

int main(int argc, char** argv) {
  try {
    const unima::bench::Args args(argc, argv,
                                  {{"host", "127.0.0.1"}, {"port", ""}, {"connections", "1"}, {"depth", "1"},
                                   {"function", "4"}, {"address", "0"}, {"quantity", "1"}, {"value", "0"},
                                   {"unit", "1"}, {"duration", "2"}, {"warmup", "0"}, {"requests", "0"},
                                   {"timeout", "5"}, {"json", "false"}},
                                  unima::bench::usage);
    if (args.text("port").empty()) throw std::runtime_error(std::string("--port is required\n") + unima::bench::usage);
    unima::bench::LoadGenerator generator(args);
    generator.run();
    generator.report(args.flag("json"));
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "unima-bench-load: %s\n", e.what());
    return 1;
  }
}
