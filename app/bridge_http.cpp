// Bridge::http_response: what each path of the HTTP server answers (SPEC §13). The
// counters come from the status document, so /metrics, /api/status and `unima-bridge
// status` never disagree.

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "app/bridge.hpp"
#include "app/bridge_core.hpp"
#include "config/register_map.hpp"
#include "config/register_map_json.hpp"
#include "metrics/prometheus.hpp"

namespace unima::app {

namespace {

constexpr auto json_type = "application/json";
io::HttpResponse not_found() {
  return {404, "text/plain; charset=utf-8", "not found: /metrics, /healthz, /api/status, /api/registers\n"};
}

}  // namespace

io::HttpResponse Bridge::http_response(std::string_view target) const {
  const auto path = target.substr(0, target.find('?'));
  if (path == "/healthz") {
    // Answered on the loop: after a stall this is the first thing to run, and says so.
    const auto silent = std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::steady_clock::now() - last_turn_);
    if (silent > stall_limit)
      return {503, "text/plain; charset=utf-8", fmt::format("stalled: the event loop did not turn for {} ms\n", silent.count())};
    if (std::chrono::steady_clock::now() < stall_reported_until_)
      return {503, "text/plain; charset=utf-8",
              fmt::format("stalled: the event loop did not turn for {} ms a moment ago\n", last_stall_.count())};
    return {200, "text/plain; charset=utf-8", "ok\n"};
  }
  if (path == "/metrics") return {200, metrics::prometheus_content_type, metrics::prometheus_text(nlohmann::json::parse(status_document()))};
  if (path == "/api/status") return {200, json_type, status_document() + "\n"};
  if (path == "/api/registers") {
    auto registers = nlohmann::json::array();
    for (const auto& row : config::register_map(core_->config)) {
      auto j = config::map_row_json(row);
      std::uint16_t value = 0;
      j["value"] = core_->space->read(row.address, std::span(&value, 1)) ? nlohmann::json(value) : nlohmann::json(nullptr);
      registers.push_back(std::move(j));
    }
    return {200, json_type, registers.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace) + "\n"};
  }
  return not_found();
}

}  // namespace unima::app
