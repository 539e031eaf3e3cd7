#pragma once
// Small helpers shared by the benchmark tools: a monotonic clock in nanoseconds, loopback
// sockets, percentiles and a "--name value" command line. Plain POSIX; no Asio and no
// libmodbus, so the load generator measures the server and not a client library.

#include <cstdint>
#include <map>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

namespace unima::bench {

/// CLOCK_MONOTONIC in nanoseconds (a vDSO call: no system call).
std::uint64_t now_ns();

/// A blocking TCP connection to host:port with TCP_NODELAY set; throws on failure.
int connect_tcp(const std::string& host, std::uint16_t port);

/// Sends all of `bytes` on a blocking socket; throws on failure.
void send_all(int fd, std::span<const std::uint8_t> bytes);

/// Reads exactly `out.size()` bytes, waiting at most `timeout_ms` in total; false on
/// time-out or when the peer closes.
bool receive_exactly(int fd, std::span<std::uint8_t> out, int timeout_ms);

/// The latency percentiles a run reports, in microseconds.
struct Percentiles {
  double p50 = 0, p99 = 0, p999 = 0, max = 0;
};
/// Sorts `samples_ns` and reads the nearest-rank percentiles from it.
Percentiles percentiles(std::vector<std::uint32_t>& samples_ns);

/// "--name value" and "--flag" options; every name must be known to the program.
class Args {
 public:
  Args(int argc, char** argv, const std::map<std::string, std::string>& defaults, const std::string& usage);
  const std::string& text(const std::string& name) const;
  std::uint64_t number(const std::string& name) const;  // decimal or 0x hex
  double real(const std::string& name) const;
  bool flag(const std::string& name) const { return text(name) == "true"; }

 private:
  std::map<std::string, std::string> values_;
};

}  // namespace unima::bench
