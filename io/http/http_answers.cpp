#include "io/http/http_answers.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "config/register_map_json.hpp"
#include "metrics/prometheus.hpp"
#include "monitor/command_filter.hpp"
#include "status/document.hpp"
#include "values/value_json.hpp"
#include "web/page_files.hpp"

namespace unima::io {

namespace {

constexpr auto json_type = "application/json";
HttpResponse not_found() {
  return {404, plain_text_type, "not found: /, /metrics, /healthz, /api/status, /api/registers, /api/events, /api/config\n", {}, {}, {}};
}

// The page runs only its own files: no inline script, nothing from elsewhere.
const std::vector<std::pair<std::string, std::string>> page_headers = {
    {"Content-Security-Policy", "default-src 'self'; img-src 'self' data:; frame-ancestors 'none'"},
    {"X-Content-Type-Options", "nosniff"},
};

// "/api/events?ad=3&fn=xx&from=0x0200&to=0x0210": the monitor pane's filter, in the
// words of `monitor --filter` (SPEC §5), one parser for both.
monitor::CommandFilter page_filter(std::string_view target) {
  const auto question = target.find('?');
  if (question == std::string_view::npos) return {};
  std::string expression(target.substr(question + 1));
  std::replace(expression.begin(), expression.end(), '&', ' ');
  return monitor::parse_command_filter(expression);
}

// An LED as the page shows it (status/activity.hpp): lit now, and the count of frames that
// blinks it — not how long ago, which would change the panel on every heartbeat.
nlohmann::json led_of(const status::Activity& activity) {
  return {{"on", activity.active}, {"frames", activity.frames}, {"lit_ms", activity.lit_ms}};
}

// The gateway's units as the page's table shows them: the counts a technician reads, the
// mean wait rounded to 0.1 ms so that the panel does not change with every microsecond.
nlohmann::json gateway_panel(const master::GatewayStatus& gateway) {
  auto units = nlohmann::json::array();
  for (const auto& u : gateway.units)
    units.push_back({{"unit", u.unit},
                     {"state", u.state},
                     {"since", u.since},
                     {"requests", u.requests},
                     {"answered", u.answered},
                     {"exceptions", u.exceptions},
                     {"timeouts", u.timeouts},
                     {"bad_frames", u.bad_frames},
                     {"busy", u.busy},
                     {"queue_depth", u.queue_depth},
                     {"wait_ms_mean", std::round(u.wait_ms.mean * 10) / 10}});
  return {{"routes", gateway.routes}, {"units", units}};
}

// The northbound box: what an operator reads of the MQTT link (SPEC §15) — not the
// published count, which grows with every document and would resend the panel with it.
nlohmann::json mqtt_panel(const mqtt::MqttStatus& mqtt) {
  nlohmann::json panel{{"broker", mqtt.broker},         {"client_id", mqtt.client_id},
                       {"connected", mqtt.connected},   {"since", mqtt.since},
                       {"last_error", mqtt.last_error}, {"session_takeovers", mqtt.session_takeovers},
                       {"last_takeover", mqtt.last_takeover}};
  panel["buffer"] = nullptr;
  if (const auto& b = mqtt.buffer)
    panel["buffer"] = {{"messages", b->messages}, {"bytes", b->bytes}, {"dropped", b->dropped}, {"history_sent", b->history_sent}};
  return panel;
}

// The Sparkplug session (SPEC §16) as the northbound box shows it.
nlohmann::json sparkplug_panel(const sparkplug::EdgeStatus& sparkplug) {
  return {{"broker", sparkplug.broker},
          {"group_id", sparkplug.group_id},
          {"edge_node_id", sparkplug.edge_node_id},
          {"connected", sparkplug.connected},
          {"born", sparkplug.born},
          {"since", sparkplug.since},
          {"last_error", sparkplug.last_error},
          {"bdSeq", sparkplug.bdSeq},
          {"seq", sparkplug.seq},
          {"births", sparkplug.births},
          {"data", sparkplug.data},
          {"commands", sparkplug.commands},
          {"primary_host", sparkplug.primary_host}};
}

// The front panel of seed 004: its LEDs, the D_N and S_N on-line, the capture indicators.
nlohmann::json panel_of(const status::Document& document) {
  nlohmann::json panel;
  if (const auto& bridge = document.bridge) {
    panel["mode"] = bridge->mode;
    panel["error"] = bridge->error;
  }
  if (document.modbus) panel["modbus"] = led_of(*document.modbus);
  if (document.unimabus) panel["unimabus"] = led_of(document.unimabus->led);
  panel["devices"] = nlohmann::json::array();
  for (const auto& device : document.devices.value_or(std::vector<unimabus::DeviceStatus>{}))
    panel["devices"].push_back({{"bank", device.bank}, {"type", device.type}, {"online", device.online}});
  panel["modules"] = nlohmann::json::array();
  for (const auto& module : document.modules.value_or(std::vector<unimabus::ModuleStatus>{}))
    panel["modules"].push_back({{"bank", module.bank}, {"online", module.online}});
  panel["indicators"] = document.indicators.value_or(std::vector<monitor::IndicatorStatus>{});
  if (document.lines) panel["serial_lines"] = *document.lines;
  if (document.gateway) panel["gateway"] = gateway_panel(*document.gateway);
  if (document.mqtt) panel["mqtt"] = mqtt_panel(*document.mqtt);
  if (document.sparkplug) panel["sparkplug"] = sparkplug_panel(*document.sparkplug);
  // The config in force: the page's Config box asks /api/config again when this changes.
  if (document.config_in_force) panel["config"] = *document.config_in_force;
  return panel;
}

// Every bank's values now, by the bank's place in the model.
std::vector<std::vector<values::Value>> all_values(const values::ValueModel& model, values::CurrentValues& current) {
  std::vector<std::vector<values::Value>> all;
  for (const auto& layout : model.banks()) all.push_back(current.of(layout.bank));
  return all;
}

// Where `row`'s register takes its value from: its bank's register, or a read block's
// source (MBS_RegR); nullopt for a write block, which holds none.
std::optional<banks::SourceRef> origin_of(const config::MapRow& row, const config::Config& config) {
  if (const auto bank = banks::parse_bank_name(row.bank)) return banks::SourceRef{*bank, row.offset, std::nullopt, {}};
  if (row.bank != "read") return std::nullopt;
  for (const auto* block : config.active_blocks())
    if (block->type == config::Block::Type::read && block->reg == row.address) return block->source;
  return std::nullopt;
}

// The values that read `row`'s register (a read block: its source's), as /api/registers
// lists them with the row, each with the bank it belongs to.
nlohmann::json row_values(const config::MapRow& row, const config::Config& config, const values::ValueModel& model,
                          const std::vector<std::vector<values::Value>>& all) {
  auto list = nlohmann::json::array();
  const auto origin = origin_of(row, config);
  for (std::size_t b = 0; origin && b < model.banks().size(); ++b) {
    const auto& layout = model.banks()[b];
    if (layout.bank != origin->bank) continue;
    for (std::size_t i = 0; i < layout.values.size(); ++i) {
      const auto& def = layout.values[i];
      if (std::find(def.offsets.begin(), def.offsets.end(), origin->offset) == def.offsets.end()) continue;
      if (origin->bit && (def.type != values::ValueType::boolean || def.first_bit != *origin->bit)) continue;
      auto entry = values::value_json(def, all[b][i]);
      entry["label"] = def.label;
      entry["type"] = values::type_name(def);
      entry["bank"] = banks::bank_name(layout.bank);
      list.push_back(std::move(entry));
    }
  }
  return list;
}

}  // namespace

web::LiveSnapshot HttpAnswers::live_snapshot() const {
  auto snapshot = live_values();
  snapshot.panel = panel_of(runtime_.status());
  return snapshot;
}

web::LiveSnapshot HttpAnswers::live_values() const {
  const auto& running = *runtime_.banks;
  web::LiveSnapshot snapshot;
  for (const auto& row : running.register_rows) {
    std::uint16_t value = 0;
    snapshot.addresses.push_back(row.address);
    snapshot.values.push_back(running.space->read(row.address, std::span(&value, 1)) ? std::optional(value) : std::nullopt);
  }
  for (const auto& layout : running.value_model.banks()) snapshot.named_banks.push_back(named_values(layout));
  return snapshot;
}

std::shared_ptr<const web::NamedValues> HttpAnswers::named_values(const values::BankValues& layout) const {
  const auto& running = *runtime_.banks;
  const auto changes = running.store->changes(layout.bank);
  auto& rendered = named_banks_[layout.bank];
  if (rendered.values && rendered.at == changes) return rendered.values;
  const auto& values = running.values->of(layout.bank);
  const auto bank = std::string(banks::bank_name(layout.bank)) + "/";
  auto named = std::make_shared<web::NamedValues>();
  named->reserve(values.size());
  for (std::size_t i = 0; i < values.size(); ++i)
    named->emplace_back(bank + layout.values[i].name, values::reading_state_json(layout.values[i], values[i]));
  rendered = {changes, std::move(named)};
  return rendered.values;
}

HttpResponse HttpAnswers::registers() const {
  const auto& running = *runtime_.banks;
  const auto values_now = all_values(running.value_model, *running.values);
  auto registers = nlohmann::json::array();
  for (const auto& row : running.register_rows) {
    auto j = config::map_row_json(row);
    std::uint16_t value = 0;
    j["value"] = running.space->read(row.address, std::span(&value, 1)) ? nlohmann::json(value) : nlohmann::json(nullptr);
    j["values"] = row_values(row, running.config, running.value_model, values_now);
    registers.push_back(std::move(j));
  }
  return {200, json_type, registers.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace) + "\n", {}, {}, {}};
}

HttpResponse HttpAnswers::answer(const HttpRequest& request) {
  const auto target = request.target;
  const auto path = target.substr(0, target.find('?'));
  if (path == HttpConfigAnswers::path || path == HttpConfigAnswers::revert_path) return config_.answer(request, path);
  if (request.method != "GET" && request.method != "HEAD")
    return {405, plain_text_type, "read only: GET or HEAD\n", {{"Allow", "GET, HEAD"}}, {}, {}};
  if (path == "/api/events") {
    monitor::CommandFilter filter;
    try {
      filter = page_filter(target);
    } catch (const monitor::FilterSyntaxError& e) {
      return {400, plain_text_type, fmt::format("{}\n", e.what()), {}, {}, {}};
    }
    HttpResponse response;
    response.stream = [this, filter](std::shared_ptr<web::EventSink> sink) {
      live_.subscribe(std::move(sink), filter, live_snapshot(), runtime_.monitor->recent());
    };
    return response;
  }
  if (const auto file = web::served_file(path))
    return {200, std::string(file->content_type), std::string(file->text), page_headers, {}, {}};
  // Answered on the loop: after a stall this is the first thing to run, and says so.
  if (path == "/healthz") {
    if (const auto stall = health_.stall(LoopHealth::Clock::now())) return {503, plain_text_type, "stalled: " + *stall + "\n", {}, {}, {}};
    return {200, plain_text_type, "ok\n", {}, {}, {}};
  }
  if (path == "/metrics") return {200, metrics::prometheus_content_type, metrics::prometheus_text(runtime_.status()), {}, {}, {}};
  if (path == "/api/status")
    return {200, json_type, nlohmann::json(runtime_.status()).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace) + "\n", {}, {}, {}};
  if (path == "/api/registers") return registers();
  return not_found();
}

}  // namespace unima::io
