#include "status/port_status.hpp"

#include "monitor/monitor_line.hpp"

namespace unima::status {

void to_json(nlohmann::json& j, const HandshakeStatus& s) {
  j = {{"completed", s.completed}, {"failed", s.failed}, {"in_progress", s.in_progress}, {"refused", s.refused}};
}

void from_json(const nlohmann::json& j, HandshakeStatus& s) {
  s.completed = j.value("completed", std::uint64_t{0});
  s.failed = j.value("failed", std::uint64_t{0});
  s.in_progress = j.value("in_progress", std::uint64_t{0});
  s.refused = j.value("refused", std::map<std::string, std::uint64_t>{});
}

namespace {
const char* const port_key = "port";
const char* const transactions_key = "transactions";
const char* const listen_key = "listen";
const char* const clients_key = "clients";
const char* const handshakes_key = "handshakes";
}  // namespace

void to_json(nlohmann::json& j, const PortStatus& s) {
  j = nlohmann::json::object();
  j[port_key] = s.port;
  j[transactions_key] = s.transactions;
  for (const auto& [state, count] : s.states) j[state] = count;
  if (s.listen) j[listen_key] = *s.listen;
  if (s.clients) j[clients_key] = *s.clients;
  if (s.handshakes) j[handshakes_key] = *s.handshakes;
}

// Every other number of the entry is a state's count.
void from_json(const nlohmann::json& j, PortStatus& s) {
  s = {};
  for (const auto& [key, value] : j.items()) {
    if (key == port_key) s.port = value.is_string() ? value.get<std::string>() : value.dump();
    else if (key == transactions_key) s.transactions = value.get<std::uint64_t>();
    else if (key == listen_key) s.listen = value.get<std::string>();
    else if (key == clients_key) s.clients = value.get<std::uint64_t>();
    else if (key == handshakes_key) s.handshakes = value.get<HandshakeStatus>();
    else if (value.is_number()) s.states[key] = value.get<std::uint64_t>();
  }
}

PortStatus port_status(const char* port, const modbus::TransactionCounters& counters) {
  PortStatus s{port, counters.transactions, {}, {}, {}, {}};
  for (std::size_t i = 0; i < modbus::transaction_state_count; ++i) {
    const auto state = static_cast<modbus::TransactionState>(i);
    s.states[std::string(monitor::state_name(state))] = counters.of(state);
  }
  return s;
}

const std::vector<Statistic<PortStatus>>& port_statistics() {
  using enum MetricType;
  static const std::vector<Statistic<PortStatus>> all{
      {"modbus_transactions_total", counter, "Modbus transactions by port and monitor state.",
       [](const PortStatus& p, Samples& out) {
         for (const auto& [state, count] : p.states) out.add(count, {{"port", p.port}, {"state", state}});
       }},
      {"modbus_clients", gauge, "Connected Modbus clients by port.",
       [](const PortStatus& p, Samples& out) { out.add(p.clients, {{"port", p.port}}); }},
  };
  return all;
}

const std::vector<Statistic<PortHandshakes>>& handshake_statistics() {
  using enum MetricType;
  static const std::vector<Statistic<PortHandshakes>> all{
      {"tls_handshakes_total", counter, "TLS handshakes completed, by port.",
       [](const PortHandshakes& h, Samples& out) { out.add(h.handshakes.completed, {{"port", h.port}}); }},
      {"tls_handshakes_failed_total", counter,
       "TLS handshakes started and not completed (an error, the deadline, the client left), by port.",
       [](const PortHandshakes& h, Samples& out) { out.add(h.handshakes.failed, {{"port", h.port}}); }},
      {"tls_handshakes_refused_total", counter,
       "TLS connections closed at accept because their host or the port had as many handshakes as allowed, by port and limit.",
       [](const PortHandshakes& h, Samples& out) {
         for (const auto& [limit, count] : h.handshakes.refused) out.add(count, {{"port", h.port}, {"limit", limit}});
       }},
      {"tls_handshakes_in_progress", gauge, "TLS handshakes in progress, by port.",
       [](const PortHandshakes& h, Samples& out) { out.add(h.handshakes.in_progress, {{"port", h.port}}); }},
  };
  return all;
}

}  // namespace unima::status
