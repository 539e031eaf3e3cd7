// metrics::prometheus_text: the status document as Prometheus text (SPEC §13). The
// format's validity is checked by promtool in the integration test; here, what each
// family says.

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "metrics/prometheus.hpp"
#include "tests/support/temp_files.hpp"

namespace unima::metrics {
namespace {

// The exposition of a document as the daemon sends it (JSON), read as its parts.
std::string exposition(const nlohmann::json& document) { return prometheus_text(document.get<status::Document>()); }

bool has_line(const std::string& text, const std::string& line) {
  return text.find("\n" + line + "\n") != std::string::npos || text.starts_with(line + "\n");
}

const auto status = nlohmann::json::parse(R"({
  "uptime_s": 42, "rss_bytes": 9437184, "error": true,
  "ports": [ {"port": "tcp", "transactions": 7, "Done": 5, "Err02": 2, "clients": 3},
             {"port": "rtu", "transactions": 1, "Done": 1},
             {"port": "tls", "transactions": 2, "Done": 2, "clients": 1,
              "handshakes": {"completed": 3, "failed": 1, "in_progress": 1,
                             "refused": {"per_host_in_progress": 4, "per_host_rate": 5, "in_progress": 0}}} ],
  "devices": [ {"bank": "D1", "type": "unigen-chp", "address": 5, "online": true, "telegrams": 12},
               {"bank": "D2", "type": null, "online": false} ],
  "modules": [ {"bank": "S1", "slot": 1, "online": false, "telegrams": 0} ],
  "unimabus": {"telegrams_ignored": 1, "telegrams_refused": 0, "clients": 2},
  "master": [ {"device": 3, "requests": 10, "answered": 8, "timeouts": 2, "exceptions": 0, "bad_frames": 0} ],
  "monitor": {"written": 100, "dropped": 4},
  "state": {"file": "/var/lib/unima-bridge/state", "records": 6, "syncs": 2, "failures": 0},
  "mqtt": {"broker": "mqtt://b", "connected": true, "connections": 3, "drops": 2, "published": 120, "session_takeovers": 1,
           "since": "2026-11-27T10:35:19.500000Z", "last_takeover": "2026-11-26T22:00:00.000000Z",
           "buffer": {"file": "/var/lib/unima-bridge/mqtt-buffer", "bytes": 4096, "messages": 3, "dropped": 5,
                      "history_sent": 40, "syncs": 9, "failures": 0}},
  "sparkplug": {"connected": true, "born": false, "bdSeq": 7, "seq": 37, "since": "2026-11-27T10:35:19.500000Z",
                "connections": 2, "births": 30, "data": 400, "deaths": 3,
                "commands": {"taken": 4, "refused": 5, "malformed": 6}},
  "http": {"logins": {"checked": 9, "wrong": 7, "peer_limited": 30, "busy": 1, "in_flight": 2}}
})");

TEST(Prometheus, EveryFamilyHasHelpAndTypeAndTheStatusValues) {
  const auto text = exposition(status);
  EXPECT_TRUE(has_line(text, "unima_bridge_mqtt_connected 1")) << text;
  EXPECT_TRUE(has_line(text, "# TYPE unima_bridge_mqtt_drops_total counter")) << text;
  EXPECT_TRUE(has_line(text, "unima_bridge_mqtt_drops_total 2")) << text;
  EXPECT_TRUE(has_line(text, "unima_bridge_mqtt_published_total 120")) << text;
  EXPECT_TRUE(has_line(text, "unima_bridge_mqtt_session_takeovers_total 1")) << text;
  EXPECT_TRUE(has_line(text, "# TYPE unima_bridge_mqtt_buffer_dropped_total counter")) << text;
  EXPECT_TRUE(has_line(text, "unima_bridge_mqtt_buffer_dropped_total 5")) << text;
  EXPECT_TRUE(has_line(text, "# TYPE unima_bridge_mqtt_buffer_bytes gauge")) << text;
  EXPECT_TRUE(has_line(text, "unima_bridge_mqtt_buffer_bytes 4096")) << text;
  EXPECT_TRUE(has_line(text, "unima_bridge_mqtt_buffer_messages 3")) << text;
  EXPECT_TRUE(has_line(text, "unima_bridge_mqtt_buffer_history_sent_total 40")) << text;
  EXPECT_TRUE(has_line(text, "unima_bridge_mqtt_buffer_syncs_total 9")) << text;
  EXPECT_TRUE(has_line(text, "unima_bridge_sparkplug_connected 1")) << text;
  EXPECT_TRUE(has_line(text, "unima_bridge_sparkplug_born 0")) << text;
  EXPECT_TRUE(has_line(text, "unima_bridge_sparkplug_bd_seq 7")) << text;
  EXPECT_TRUE(has_line(text, "# TYPE unima_bridge_sparkplug_births_total counter")) << text;
  EXPECT_TRUE(has_line(text, "unima_bridge_sparkplug_births_total 30")) << text;
  EXPECT_TRUE(has_line(text, "unima_bridge_sparkplug_data_total 400")) << text;
  EXPECT_TRUE(has_line(text, "unima_bridge_sparkplug_device_deaths_total 3")) << text;
  EXPECT_TRUE(has_line(text, "# TYPE unima_bridge_mqtt_state_since_timestamp_seconds gauge")) << text;
  EXPECT_TRUE(has_line(text, "unima_bridge_mqtt_state_since_timestamp_seconds 1795775719.5")) << text;
  EXPECT_TRUE(has_line(text, "unima_bridge_mqtt_last_session_takeover_timestamp_seconds 1795730400.0")) << text;
  EXPECT_TRUE(has_line(text, "unima_bridge_sparkplug_seq 37")) << text;
  EXPECT_TRUE(has_line(text, "unima_bridge_sparkplug_state_since_timestamp_seconds 1795775719.5")) << text;
  EXPECT_TRUE(has_line(text, R"(unima_bridge_sparkplug_commands_total{outcome="taken"} 4)")) << text;
  EXPECT_TRUE(has_line(text, R"(unima_bridge_sparkplug_commands_total{outcome="refused"} 5)")) << text;
  EXPECT_TRUE(has_line(text, R"(unima_bridge_sparkplug_commands_total{outcome="malformed"} 6)")) << text;
  EXPECT_TRUE(has_line(text, "# HELP unima_bridge_uptime_seconds Seconds since the daemon started.")) << text;
  EXPECT_TRUE(has_line(text, "# TYPE unima_bridge_uptime_seconds gauge")) << text;
  EXPECT_TRUE(has_line(text, "unima_bridge_uptime_seconds 42")) << text;
  EXPECT_TRUE(has_line(text, "unima_bridge_resident_memory_bytes 9437184")) << text;
  EXPECT_TRUE(has_line(text, "unima_bridge_modbus_error 1")) << text;
  EXPECT_TRUE(has_line(text, "# TYPE unima_bridge_modbus_transactions_total counter")) << text;
  EXPECT_TRUE(has_line(text, R"(unima_bridge_modbus_transactions_total{port="tcp",state="Done"} 5)")) << text;
  EXPECT_TRUE(has_line(text, R"(unima_bridge_modbus_transactions_total{port="tcp",state="Err02"} 2)")) << text;
  EXPECT_TRUE(has_line(text, R"(unima_bridge_modbus_transactions_total{port="rtu",state="Done"} 1)")) << text;
  EXPECT_TRUE(has_line(text, R"(unima_bridge_modbus_clients{port="tcp"} 3)")) << text;
  EXPECT_EQ(text.find(R"(unima_bridge_modbus_clients{port="rtu"})"), std::string::npos) << text;  // no such figure
  EXPECT_TRUE(has_line(text, "# TYPE unima_bridge_tls_handshakes_total counter")) << text;
  EXPECT_TRUE(has_line(text, R"(unima_bridge_tls_handshakes_total{port="tls"} 3)")) << text;
  EXPECT_TRUE(has_line(text, R"(unima_bridge_tls_handshakes_failed_total{port="tls"} 1)")) << text;
  EXPECT_TRUE(has_line(text, R"(unima_bridge_tls_handshakes_refused_total{port="tls",limit="per_host_rate"} 5)")) << text;
  EXPECT_TRUE(has_line(text, R"(unima_bridge_tls_handshakes_refused_total{port="tls",limit="in_progress"} 0)")) << text;
  EXPECT_TRUE(has_line(text, R"(unima_bridge_tls_handshakes_in_progress{port="tls"} 1)")) << text;
  EXPECT_EQ(text.find(R"(unima_bridge_tls_handshakes_total{port="tcp"})"), std::string::npos) << text;
  EXPECT_EQ(text.find(R"(state="handshakes")"), std::string::npos) << text;  // not a transaction state
  EXPECT_TRUE(has_line(text, R"(unima_bridge_device_online{bank="D1",type="unigen-chp"} 1)")) << text;
  EXPECT_TRUE(has_line(text, R"(unima_bridge_device_telegrams_total{bank="D1",type="unigen-chp"} 12)")) << text;
  EXPECT_EQ(text.find(R"(bank="D2")"), std::string::npos) << text;  // not configured: not a device
  EXPECT_TRUE(has_line(text, R"(unima_bridge_module_online{bank="S1"} 0)")) << text;
  EXPECT_TRUE(has_line(text, "unima_bridge_feed_clients 2")) << text;
  EXPECT_TRUE(has_line(text, R"(unima_bridge_master_timeouts_total{device="3"} 2)")) << text;
  EXPECT_TRUE(has_line(text, "unima_bridge_monitor_lines_dropped_total 4")) << text;
  EXPECT_TRUE(has_line(text, "unima_bridge_state_syncs_total 2")) << text;
  EXPECT_TRUE(has_line(text, "unima_bridge_http_password_checks_total 9")) << text;
  EXPECT_TRUE(has_line(text, "unima_bridge_http_password_checks_in_flight 2")) << text;
  EXPECT_TRUE(has_line(text, R"(unima_bridge_http_logins_refused_total{reason="wrong"} 7)")) << text;
  EXPECT_TRUE(has_line(text, R"(unima_bridge_http_logins_refused_total{reason="peer_limited"} 30)")) << text;
  EXPECT_TRUE(has_line(text, R"(unima_bridge_http_logins_refused_total{reason="busy"} 1)")) << text;
  EXPECT_EQ(text.back(), '\n');
}

TEST(Prometheus, LabelValuesAreEscaped) {
  auto odd = status;
  odd["devices"][0]["type"] = "a\"b\\c\nd";
  const auto text = exposition(odd);
  EXPECT_TRUE(has_line(text, R"(unima_bridge_device_online{bank="D1",type="a\"b\\c\nd"} 1)")) << text;
}

// No session taken over yet (null): no takeover time, rather than the epoch.
TEST(Prometheus, NoSessionTakeoverYetLeavesItsTimeOut) {
  auto quiet = status;
  quiet["mqtt"]["last_takeover"] = nullptr;
  const auto text = exposition(quiet);
  EXPECT_TRUE(has_line(text, "# TYPE unima_bridge_mqtt_last_session_takeover_timestamp_seconds gauge")) << text;
  EXPECT_EQ(text.find("\nunima_bridge_mqtt_last_session_takeover_timestamp_seconds "), std::string::npos) << text;
  EXPECT_TRUE(has_line(text, "unima_bridge_mqtt_state_since_timestamp_seconds 1795775719.5")) << text;
}

// modbus.gateway (SPEC §14): each unit's counters with a unit label, its queue depth and
// whether it answers as gauges, and its wait as a summary (sum and count) and the longest.
TEST(Prometheus, TheGatewaysUnitsAreCountedByUnit) {
  const auto gateway = nlohmann::json::parse(R"({"gateway": {"routes": "5-7", "units": [
    {"unit": 5, "state": "answering", "since": null, "requests": 12, "answered": 10, "exceptions": 1, "timeouts": 0,
     "bad_frames": 1, "busy": 2, "cache_hits": 4, "queue_depth": 3,
     "wait_ms": {"last": 1.5, "mean": 2.5, "max": 40.0, "count": 12, "sum": 30.0}},
    {"unit": 7, "state": "not answering", "since": "2026-11-27 08:10:01.532000", "requests": 3, "answered": 0,
     "exceptions": 0, "timeouts": 3, "bad_frames": 0, "busy": 0, "cache_hits": 0, "queue_depth": 0,
     "wait_ms": {"last": 0, "mean": 0, "max": 0, "count": 3, "sum": 0}} ]}})");
  const auto text = exposition(gateway);
  EXPECT_TRUE(has_line(text, "# TYPE unima_bridge_gateway_requests_total counter")) << text;
  EXPECT_TRUE(has_line(text, R"(unima_bridge_gateway_requests_total{unit="5"} 12)")) << text;
  EXPECT_TRUE(has_line(text, R"(unima_bridge_gateway_answered_total{unit="5"} 10)")) << text;
  EXPECT_TRUE(has_line(text, R"(unima_bridge_gateway_exceptions_total{unit="5"} 1)")) << text;
  EXPECT_TRUE(has_line(text, R"(unima_bridge_gateway_timeouts_total{unit="7"} 3)")) << text;
  EXPECT_TRUE(has_line(text, R"(unima_bridge_gateway_bad_frames_total{unit="5"} 1)")) << text;
  EXPECT_TRUE(has_line(text, R"(unima_bridge_gateway_busy_total{unit="5"} 2)")) << text;
  EXPECT_TRUE(has_line(text, R"(unima_bridge_gateway_cache_hits_total{unit="5"} 4)")) << text;
  EXPECT_TRUE(has_line(text, "# TYPE unima_bridge_gateway_queue_depth gauge")) << text;
  EXPECT_TRUE(has_line(text, R"(unima_bridge_gateway_queue_depth{unit="5"} 3)")) << text;
  EXPECT_TRUE(has_line(text, R"(unima_bridge_gateway_answering{unit="5"} 1)")) << text;
  EXPECT_TRUE(has_line(text, R"(unima_bridge_gateway_answering{unit="7"} 0)")) << text;
  EXPECT_TRUE(has_line(text, "# TYPE unima_bridge_gateway_wait_seconds summary")) << text;
  EXPECT_TRUE(has_line(text, R"(unima_bridge_gateway_wait_seconds_sum{unit="5"} 0.03)")) << text;
  EXPECT_TRUE(has_line(text, R"(unima_bridge_gateway_wait_seconds_count{unit="5"} 12)")) << text;
  EXPECT_TRUE(has_line(text, R"(unima_bridge_gateway_wait_max_seconds{unit="5"} 0.04)")) << text;
}

// Each RS-485 line's families are labelled by the line and its role (SPEC §18); a
// bridge without a line has none of them.
TEST(Prometheus, EachLineIsCountedByItsLabel) {
  auto document = status;
  document["lines"] = nlohmann::json::parse(R"([
    {"line": "scada", "role": "slave", "device": "/dev/ttyS0", "settings": "19200 8E1", "open": true,
     "frames_sent": 10, "frames_received": 12, "errors": 1, "queue": 0},
    {"line": "field", "role": "master", "device": "/dev/ttyS1", "settings": "9600 8N1", "open": false,
     "frames_sent": 30, "frames_received": 27, "errors": 3, "queue": 4}])");
  const auto text = exposition(document);
  EXPECT_TRUE(has_line(text, "# TYPE unima_bridge_line_frames_sent_total counter")) << text;
  EXPECT_TRUE(has_line(text, R"(unima_bridge_line_open{line="scada",role="slave"} 1)")) << text;
  EXPECT_TRUE(has_line(text, R"(unima_bridge_line_open{line="field",role="master"} 0)")) << text;
  EXPECT_TRUE(has_line(text, R"(unima_bridge_line_frames_sent_total{line="scada",role="slave"} 10)")) << text;
  EXPECT_TRUE(has_line(text, R"(unima_bridge_line_frames_received_total{line="field",role="master"} 27)")) << text;
  EXPECT_TRUE(has_line(text, R"(unima_bridge_line_errors_total{line="field",role="master"} 3)")) << text;
  EXPECT_TRUE(has_line(text, "# TYPE unima_bridge_line_queue gauge")) << text;
  EXPECT_TRUE(has_line(text, R"(unima_bridge_line_queue{line="field",role="master"} 4)")) << text;
  EXPECT_EQ(exposition(status).find("unima_bridge_line_"), std::string::npos);
}

TEST(Prometheus, AnEmptyDocumentGivesOnlyHelpAndType) {
  const auto text = exposition(nlohmann::json::object());
  for (std::size_t at = 0; at < text.size();) {
    const auto end = text.find('\n', at);
    EXPECT_EQ(text[at], '#') << text.substr(at, end - at);
    at = end + 1;
  }
}

// The daemon's own documents (tests/golden/status_*.json, kept by the integration test
// StatusKeys with every part on) give exactly the exposition they gave before the status
// was typed: every family, label and value. UNIMA_UPDATE_GOLDEN=1 rewrites the text.
TEST(Prometheus, TheDaemonsDocumentsGiveTheGoldenExposition) {
  const auto golden = std::filesystem::path(UNIMA_SOURCE_DIR) / "tests" / "golden";
  for (const std::string name : {"slave", "master"}) {
    const auto document = nlohmann::json::parse(test_support::read_file(golden / ("status_" + name + ".json")));
    const auto text = exposition(document);
    const auto file = golden / ("prometheus_" + name + ".txt");
    if (const char* update = std::getenv("UNIMA_UPDATE_GOLDEN"); update && *update) test_support::write_file(file, text);
    EXPECT_EQ(text, test_support::read_file(file)) << name;
  }
}

}  // namespace
}  // namespace unima::metrics
