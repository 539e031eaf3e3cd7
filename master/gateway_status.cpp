#include "master/gateway_status.hpp"

#include <string>

namespace unima::master {

namespace {

using status::Labels;
using status::Samples;

Labels device_label(const MasterDeviceStatus& d) { return {{"device", std::to_string(d.device)}}; }
Labels unit_label(const GatewayUnitStatus& u) { return {{"unit", std::to_string(u.unit)}}; }
double seconds(double milliseconds) { return milliseconds / 1000.0; }

}  // namespace

const std::vector<status::Statistic<MasterDeviceStatus>>& master_device_statistics() {
  using enum status::MetricType;
  static const std::vector<status::Statistic<MasterDeviceStatus>> all{
      {"master_requests_total", counter, "Requests the master sent to a foreign slave, retries and probes included.",
       [](const MasterDeviceStatus& d, Samples& out) { out.add(d.requests, device_label(d)); }},
      {"master_answered_total", counter, "Good answers from a foreign slave.",
       [](const MasterDeviceStatus& d, Samples& out) { out.add(d.answered, device_label(d)); }},
      {"master_timeouts_total", counter, "Requests to a foreign slave that timed out.",
       [](const MasterDeviceStatus& d, Samples& out) { out.add(d.timeouts, device_label(d)); }},
      {"master_exceptions_total", counter, "Exception answers from a foreign slave.",
       [](const MasterDeviceStatus& d, Samples& out) { out.add(d.exceptions, device_label(d)); }},
      {"master_bad_frames_total", counter, "Bad frames from a foreign slave (CRC, length, function, address).",
       [](const MasterDeviceStatus& d, Samples& out) { out.add(d.bad_frames, device_label(d)); }},
  };
  return all;
}

// modbus.gateway (SPEC §14), by unit id: what its clients got, what waits, whether it answers.
const std::vector<status::Statistic<GatewayUnitStatus>>& gateway_unit_statistics() {
  using enum status::MetricType;
  static const std::vector<status::Statistic<GatewayUnitStatus>> all{
      {"gateway_requests_total", counter, "Requests the gateway sent on the line to a unit (never retried).",
       [](const GatewayUnitStatus& u, Samples& out) { out.add(u.requests, unit_label(u)); }},
      {"gateway_answered_total", counter, "Answers with data from a unit behind the gateway.",
       [](const GatewayUnitStatus& u, Samples& out) { out.add(u.answered, unit_label(u)); }},
      {"gateway_exceptions_total", counter, "The slave's own exception answers, passed back to the client.",
       [](const GatewayUnitStatus& u, Samples& out) { out.add(u.exceptions, unit_label(u)); }},
      {"gateway_timeouts_total", counter, "Forwarded requests without an answer (the client got exception 0B).",
       [](const GatewayUnitStatus& u, Samples& out) { out.add(u.timeouts, unit_label(u)); }},
      {"gateway_bad_frames_total", counter,
       "Forwarded requests answered with a bad frame: CRC, length, address (the client got 0B).",
       [](const GatewayUnitStatus& u, Samples& out) { out.add(u.bad_frames, unit_label(u)); }},
      {"gateway_busy_total", counter, "Requests that could not start on the line within wait (the client got exception 06).",
       [](const GatewayUnitStatus& u, Samples& out) { out.add(u.busy, unit_label(u)); }},
      {"gateway_cache_hits_total", counter, "Reads answered from the gateway's cache, without the line.",
       [](const GatewayUnitStatus& u, Samples& out) { out.add(u.cache_hits, unit_label(u)); }},
      {"gateway_queue_depth", gauge, "Requests for a unit waiting for the line now.",
       [](const GatewayUnitStatus& u, Samples& out) { out.add(u.queue_depth, unit_label(u)); }},
      {"gateway_answering", gauge, "1 while a unit behind the gateway answers; 0 after 3 failed requests in a row.",
       [](const GatewayUnitStatus& u, Samples& out) { out.add(u.state == "answering", unit_label(u)); }},
      {"gateway_wait_seconds", summary, "Time a forwarded request waited for the line, from the client to its frame.",
       [](const GatewayUnitStatus& u, Samples& out) {
         out.add(seconds(u.wait_ms.sum), unit_label(u), "_sum").add(u.wait_ms.count, unit_label(u), "_count");
       }},
      {"gateway_wait_max_seconds", gauge, "The longest a forwarded request for a unit has waited for the line.",
       [](const GatewayUnitStatus& u, Samples& out) { out.add(seconds(u.wait_ms.max), unit_label(u)); }},
  };
  return all;
}

}  // namespace unima::master
