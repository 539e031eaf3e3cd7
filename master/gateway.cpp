#include "master/gateway.hpp"

#include <utility>

#include "modbus/request_handler.hpp"

namespace unima::master {

Bytes gateway_exception(std::uint8_t function, modbus::ExceptionCode code) {
  Bytes pdu(2);
  modbus::write_exception(function, code, pdu);
  return pdu;
}

Gateway::Gateway(Settings settings) : settings_(settings), queue_(settings.wait) {
  if (settings_.cache > Clock::duration::zero()) cache_.emplace(settings_.cache);
}

Gateway::Arrival Gateway::arrive(const GatewayQueue::Asker& asker, std::uint8_t unit, std::span<const std::uint8_t> pdu,
                                 TimePoint now) {
  auto& counters = units_[unit];
  if (cache_) {
    if (auto cached = cache_->answer(unit, pdu, now)) {
      ++counters.cache_hits;
      return Arrival{std::move(cached), std::nullopt};
    }
    // A write empties the unit's cache now, and again when it goes on the line (began).
    if (!GatewayCache::is_read(pdu)) cache_->written(unit);
  }
  const auto ticket = queue_.push(asker, unit, now);
  if (!ticket) ++counters.busy;
  return Arrival{std::nullopt, ticket};
}

void Gateway::began(const GatewayQueue::Request& next, std::span<const std::uint8_t> pdu, TimePoint now) {
  queue_.began(next.ticket);
  auto& counters = units_[next.unit];
  ++counters.requests;
  counters.wait.took_line(now - next.queued);
  if (cache_ && !GatewayCache::is_read(pdu)) cache_->written(next.unit);
}

std::chrono::milliseconds Gateway::timeout(std::optional<Clock::duration> device_timeout) const {
  if (settings_.timeout) return *settings_.timeout;
  if (device_timeout) return std::chrono::duration_cast<std::chrono::milliseconds>(*device_timeout);
  return std::chrono::seconds(1);
}

Gateway::Outcome Gateway::finished(std::uint8_t unit, std::span<const std::uint8_t> pdu,
                                   std::span<const std::uint8_t> frame, TimePoint now,
                                   std::chrono::system_clock::time_point sent) {
  Outcome outcome;
  outcome.result = check_forwarded_rtu_answer(frame, unit, pdu);
  const bool cacheable = !std::exchange(after_timeout_, outcome.result.status == ResponseStatus::timeout);
  const auto& result = outcome.result;
  auto& counters = units_[unit];
  switch (result.status) {
    case ResponseStatus::ok: ++counters.answered; break;
    case ResponseStatus::exception: ++counters.exceptions; break;
    case ResponseStatus::timeout: ++counters.timeouts; break;
    default: ++counters.bad_frames;
  }
  outcome.transition = slave_answered(result) ? counters.answering.answered() : counters.answering.failed(sent);
  if (result.status == ResponseStatus::ok || result.status == ResponseStatus::exception) {
    // Only the slave's data is kept (GatewayCache keeps no exception).
    if (cache_ && cacheable) cache_->answered(unit, pdu, result.pdu, now);
    outcome.answer.assign(result.pdu.begin(), result.pdu.end());
  } else {
    // No answer, a bad CRC, another slave's answer: the target failed to respond (SPEC §14).
    outcome.answer = gateway_exception(pdu[0], modbus::ExceptionCode::gateway_target_failed);
  }
  return outcome;
}

std::vector<GatewayQueue::Request> Gateway::expire(TimePoint now) {
  auto expired = queue_.expire(now);
  for (const auto& request : expired) ++units_[request.unit].busy;
  return expired;
}

std::vector<Gateway::Ticket> Gateway::client_gone(std::uint64_t client) {
  std::vector<Ticket> tickets;
  for (const auto& request : queue_.drop_client(client)) tickets.push_back(request.ticket);
  return tickets;
}

void Gateway::device_written(std::uint8_t unit) {
  if (cache_) cache_->written(unit);
}

}  // namespace unima::master
