#include "io/master/master_port.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "io/master/master_rtu_link.hpp"
#include "io/master/master_tcp_link.hpp"
#include "master/master_codec.hpp"
#include "modbus/request_handler.hpp"
#include "monitor/monitor_line.hpp"
#include "platform/peer_warnings.hpp"

namespace unima::io {

namespace {

using master::MasterScheduler;
using master::ResponseStatus;
using modbus::TransactionState;

std::string hex(std::span<const std::uint8_t> bytes) {
  std::string out;
  for (auto b : bytes) out += fmt::format("{}{:02X}", out.empty() ? "" : " ", b);
  return out.empty() ? "-" : out;
}

std::string range(const master::PlannedRequest& r) {
  return r.count == 1 ? fmt::format("{}", r.first) : fmt::format("{}..{}", r.first, r.first + r.count - 1);
}

// A poll's and a forwarded transaction's alike: anything but a good answer lights the
// Error LED (C+0x13 bit 15, SPEC §8), the slave's exception included.
bool is_fault(TransactionState state) { return state != TransactionState::done; }

std::string outcome_text(const master::MasterResponse& r) {
  if (r.status != ResponseStatus::exception) return std::string(response_status_name(r.status));
  return fmt::format("exception {:02X}", static_cast<unsigned>(r.exception));
}

}  // namespace

std::string describe_master_transaction(const modbus::Transaction& t) {
  const auto* port = t.port == modbus::PortKind::gateway ? "gw:" : t.peer.empty() ? "rtu" : "tcp:";
  return fmt::format("{} {}{} {} -> {}", monitor::state_name(t.state), port, t.peer, hex(t.query), hex(t.response));
}

std::shared_ptr<MasterPort> MasterPort::create(asio::io_context& io, const config::MasterRecipe& recipe, Hooks hooks) {
  std::shared_ptr<MasterLink> link;
  if (recipe.serial)
    link = std::make_shared<MasterRtuLink>(io, *recipe.serial);
  else
    link = std::make_shared<MasterTcpLink>(io, recipe.tcp, recipe.tcp_target);
  return std::make_shared<MasterPort>(io, recipe.setup, std::move(link), std::move(hooks), recipe.gateway);
}

void MasterPort::take_positions(const config::MasterSetup& setup) {
  for (std::size_t i = 0; i < setup_.blocks.size() && i < setup.blocks.size(); ++i)
    setup_.blocks[i].origin = setup.blocks[i].origin;
}

MasterPort::MasterPort(asio::io_context& io, config::MasterSetup setup, std::shared_ptr<MasterLink> link, Hooks hooks,
                       std::optional<config::GatewayConfig> gateway)
    : setup_(std::move(setup)),
      link_(std::move(link)),
      hooks_(std::move(hooks)),
      wake_timer_(io),
      stale_timer_(io.get_executor(), [this] { return staleness_ ? staleness_->next_expiry() : std::nullopt; },
                   [this] { expire_stale_values(); }),
      executor_(io.get_executor()),
      gateway_config_(std::move(gateway)),
      expiry_timer_(io) {}

MasterPort::~MasterPort() { stop(); }

void MasterPort::start() {
  if (running_) return;
  running_ = true;
  const auto now = Clock::now();
  auto plan = config::master_plan(setup_);
  for (const auto& r : plan) counters_[r.device];
  scheduler_.emplace(std::move(plan), setup_.scheduler, setup_.devices, now);
  std::vector<std::optional<Clock::duration>> stale_limits;
  for (std::size_t i = 0; i < setup_.blocks.size(); ++i)
    stale_limits.push_back(setup_.blocks[i].is_read() ? std::optional<Clock::duration>(setup_.stale_after[i]) : std::nullopt);
  staleness_.emplace(std::move(stale_limits), now);
  skip_warned_.assign(setup_.blocks.size(), false);
  if (gateway_config_) gateway_.emplace(master::Gateway::Settings{gateway_config_->wait, gateway_config_->timeout, gateway_config_->cache});
  spdlog::info("modbus master: {}, {} requests for {} blocks", link_->describe(), scheduler_->request_count(),
               setup_.blocks.size());
  stale_timer_.watch();
  link_->on_reopened([this] {
    if (!running_) return;
    scheduler_->line_back(Clock::now());
    if (!in_flight_) pump();
  });
  pump();
}

void MasterPort::stop() {
  if (!running_) return;
  running_ = false;
  link_->on_reopened(nullptr);
  link_->close();
  wake_timer_.cancel();
  stale_timer_.cancel();
  expiry_timer_.cancel();
  in_flight_ = false;
  // The clients waiting for the line get an answer: nothing behind the gateway will give one.
  if (on_line_) refuse(*std::exchange(on_line_, std::nullopt), modbus::ExceptionCode::gateway_target_failed);
  for (auto& [ticket, waiting] : waiting_) refuse(std::move(waiting), modbus::ExceptionCode::gateway_target_failed);
  waiting_.clear();
  gateway_.reset();
  for (const auto& [device, c] : counters_)
    spdlog::info("modbus master: device {}: {} requests, {} answered, {} time-outs, {} bad frames, {} exceptions, "
                 "{} retries, {} probes, {} sends skipped{}",
                 device, c.requests, c.answered, c.timeouts, c.bad_frames, c.exceptions, c.retries, c.probes, c.skipped,
                 c.degraded ? ", degraded" : "");
}

void MasterPort::pump() {
  while (running_ && !in_flight_) {
    const auto now = Clock::now();
    const auto decision = scheduler_->decide(now);
    auto wake = decision.wake;
    if (gateway_) {
      if (const auto next = gateway_->next(decision.send.has_value())) {
        const auto ready = scheduler_->ready_for(next->unit);
        if (ready <= now) {
          forward_now(*next, now);
          continue;
        }
        wake = std::min(wake, ready);
      }
    }
    if (decision.send) {
      send(*decision.send);
      continue;
    }
    if (wake == Clock::time_point::max()) return;
    wake_timer_.expires_at(wake);
    wake_timer_.async_wait([weak = weak_from_this()](const boost::system::error_code& ec) {
      const auto self = weak.lock();
      if (!ec && self) self->pump();
    });
    return;
  }
}

void MasterPort::send(const MasterScheduler::Choice& choice) {
  const auto now = Clock::now();
  const auto& request = scheduler_->request(choice.request);
  master::Bytes pdu;
  if (request.is_read()) {
    pdu = master::read_request_pdu(request.function, request.first, request.count);
  } else {
    const auto index = request.blocks.front();
    const auto& block = setup_.blocks[index];
    const auto value = hooks_.read_source(*setup_.sources[index]);
    if (!value) {
      // A "not measured" 0x7FFF is no value to put into a drive.
      if (!skip_warned_[index])
        spdlog::warn("modbus master: {}: the send block's source {} is not measured; nothing is written until it is",
                     block.origin, setup_.sources[index]->text);
      skip_warned_[index] = true;
      ++counters_[request.device].skipped;
      scheduler_->skip(choice, now);
      return;
    }
    skip_warned_[index] = false;
    pdu = master::write_request_pdu(request.function, request.first, master::send_values(block, *value));
  }
  auto& counters = counters_[request.device];
  ++counters.requests;
  if (choice.attempt > 0) ++counters.retries;
  if (choice.probe) ++counters.probes;
  scheduler_->begin(choice, now);
  if (gateway_) {
    gateway_->poll_began();
    // The master's own send changes the slave as a client's write would.
    if (!request.is_read()) gateway_->device_written(request.device);
  }
  in_flight_ = true;
  const auto sent = std::chrono::system_clock::now();
  if (hooks_.on_query_sent) hooks_.on_query_sent(sent);
  // A frame to a device in doubt may wait less than its time-out: only as long as the line
  // has room before the next request of a live device.
  const auto wait = choice.timeout > MasterScheduler::Duration::zero() ? choice.timeout
                                                                       : scheduler_->timing(request.device).response_timeout;
  const auto timeout = std::chrono::duration_cast<std::chrono::milliseconds>(wait);
  waiting_for_answer_ = timeout;
  link_->transact(request.device, pdu, timeout,
                  [weak = weak_from_this(), choice, pdu, sent](master::Bytes query, master::Bytes response) {
                    if (const auto self = weak.lock())
                      self->finished(choice, pdu, sent, std::move(query), std::move(response));
                  });
}

void MasterPort::count_on_line(const master::Bytes& query, const master::MasterResponse& result) {
  if (!query.empty()) ++line_counters_.frames_sent;
  switch (result.status) {
    case ResponseStatus::ok:
    case ResponseStatus::exception: ++line_counters_.frames_received; break;
    default: ++line_counters_.errors; break;
  }
}

void MasterPort::finished(const MasterScheduler::Choice& choice, const master::Bytes& pdu,
                          std::chrono::system_clock::time_point sent, master::Bytes query, master::Bytes response) {
  if (!running_) return;
  in_flight_ = false;
  const auto now = Clock::now();
  const auto request = scheduler_->request(choice.request);  // a copy: replace() below may move it
  const auto result = link_->check(response, request.device, pdu);
  const auto state = master::transaction_state(result);
  count_on_line(query, result);
  const auto peer = link_->peer();
  if (hooks_.on_transaction)
    hooks_.on_transaction(modbus::Transaction{modbus::PortKind::master, peer, sent, state, query, response, false});

  auto& counters = counters_[request.device];
  switch (result.status) {
    case ResponseStatus::ok: ++counters.answered; break;
    case ResponseStatus::timeout: ++counters.timeouts; break;
    case ResponseStatus::exception: ++counters.exceptions; break;
    default: ++counters.bad_frames;
  }
  if (is_fault(state) && hooks_.on_fault) hooks_.on_fault();

  if (result.status == ResponseStatus::ok && request.is_read()) take_values(request, result, now);
  if (auto parts = master::split_after(request, result, setup_.blocks); !parts.empty()) {
    spdlog::warn("modbus master: device {} answered exception 02 to function {} {}; reading it in {} requests "
                 "from now on",
                 request.device, request.function, range(request), parts.size());
    scheduler_->replace(choice.request, std::move(parts));
  }
  const auto outcome = master::slave_answered(result) ? MasterScheduler::Outcome::answered : MasterScheduler::Outcome::failed;
  const auto transition = scheduler_->end(choice, outcome, now);
  const bool timed_out = result.status == ResponseStatus::timeout;
  if (timed_out) scheduler_->timed_out(now, waiting_for_answer_);
  if (gateway_) gateway_->poll_ended(timed_out);
  switch (transition) {
    case MasterScheduler::Transition::degraded:
      counters.degraded = true;
      spdlog::warn("modbus master: device {} degraded: {} ({}); its requests stop, a probe goes every {} ms",
                   request.device, outcome_text(result), link_->describe(),
                   std::chrono::duration_cast<std::chrono::milliseconds>(scheduler_->probe_interval(request.device)).count());
      break;
    case MasterScheduler::Transition::recovered:
      counters.degraded = false;
      spdlog::info("modbus master: device {} answers again", request.device);
      break;
    case MasterScheduler::Transition::none: break;
  }
  if (result.status != ResponseStatus::ok && result.status != ResponseStatus::timeout)
    spdlog::debug("modbus master: device {} function {} {}: {}", request.device, request.function, range(request),
                  outcome_text(result));
  pump();
}

void MasterPort::forward(GatewayRequest request, GatewayAnswer answer) {
  if (!running_ || !gateway_) return refuse(Forwarded{std::move(request), std::move(answer)},
                                            modbus::ExceptionCode::gateway_target_failed);
  const master::GatewayQueue::Asker asker{request.client, std::string(platform::peer_host(request.peer)), request.priority};
  auto arrival = gateway_->arrive(asker, request.unit, request.pdu, Clock::now());
  if (arrival.cached) return answer_from_cache(Forwarded{std::move(request), std::move(answer)}, std::move(*arrival.cached));
  if (!arrival.ticket) {
    platform::warn_from_peer("modbus gateway: requests refused busy", request.peer,
                             "modbus gateway: {} has {} requests waiting for the line, the most one host may have: "
                             "answered busy (0x06)",
                             platform::peer_host(request.peer), master::GatewayQueue::most_waiting_per_host);
    return refuse(Forwarded{std::move(request), std::move(answer)}, modbus::ExceptionCode::server_device_busy);
  }
  waiting_.emplace(*arrival.ticket, Forwarded{std::move(request), std::move(answer)});
  if (gateway_->waiting() == 1) expire_waiting();  // the timer was idle: arm it
  if (in_flight_) return;  // the line's next turn is decided when its transaction ends
  // Not from within the client's call: its answer must not come back into it.
  asio::post(executor_, [weak = weak_from_this()] {
    if (const auto self = weak.lock(); self && !self->in_flight_) self->pump();
  });
}

void MasterPort::client_gone(std::uint64_t client) {
  if (!gateway_) return;
  const auto dropped = gateway_->client_gone(client);
  for (const auto ticket : dropped) waiting_.erase(ticket);
  if (!dropped.empty())
    spdlog::debug("modbus gateway: client {} went; {} of its requests left the queue", client, dropped.size());
}

void MasterPort::expire_waiting() {
  if (!running_ || !gateway_) return;
  for (const auto& expired : gateway_->expire(Clock::now())) {
    auto waiting = waiting_.extract(expired.ticket);
    if (waiting.empty()) continue;
    refuse(std::move(waiting.mapped()), modbus::ExceptionCode::server_device_busy);
  }
  const auto next = gateway_->next_expiry();
  if (!next) return;
  expiry_timer_.expires_at(*next);
  expiry_timer_.async_wait([weak = weak_from_this()](const boost::system::error_code& ec) {
    if (const auto self = weak.lock(); self && !ec) self->expire_waiting();
  });
}

// A forwarded request is sent as it came and never retried: the client decides whether
// to ask again (a write twice may not be what it wants).
void MasterPort::forward_now(const master::GatewayQueue::Request& next, Clock::time_point now) {
  auto waiting = waiting_.extract(next.ticket);
  gateway_->began(next, waiting.empty() ? std::span<const std::uint8_t>() : waiting.mapped().request.pdu, now);
  if (waiting.empty()) return;
  on_line_ = std::move(waiting.mapped());
  in_flight_ = true;
  const auto sent = std::chrono::system_clock::now();
  if (hooks_.on_query_sent) hooks_.on_query_sent(sent);
  const auto unit = on_line_->request.unit;
  const auto device_timeout = scheduler_->knows(unit) ? std::optional(scheduler_->timing(unit).response_timeout) : std::nullopt;
  waiting_for_answer_ = gateway_->timeout(device_timeout);
  link_->transact(unit, on_line_->request.pdu, waiting_for_answer_,
                  [weak = weak_from_this(), now, sent](master::Bytes query, master::Bytes response) {
                    const auto self = weak.lock();
                    if (!self || !self->on_line_) return;
                    self->forwarded(*std::exchange(self->on_line_, std::nullopt), now, sent, query, response);
                  });
}

void MasterPort::forwarded(const Forwarded& forwarded, Clock::time_point started,
                           std::chrono::system_clock::time_point sent, const master::Bytes& query,
                           const master::Bytes& response) {
  if (!running_) return;
  in_flight_ = false;
  const auto& request = forwarded.request;
  const auto now = Clock::now();
  scheduler_->line_used(request.unit, started, now);
  auto outcome = gateway_->finished(request.unit, request.pdu, response, now, sent);
  if (outcome.result.status == ResponseStatus::timeout) scheduler_->timed_out(now, waiting_for_answer_);
  const auto state = master::transaction_state(outcome.result);
  count_on_line(query, outcome.result);
  if (hooks_.on_transaction)
    hooks_.on_transaction(modbus::Transaction{modbus::PortKind::gateway, request.peer, sent, state, query, response, false});
  if (is_fault(state) && hooks_.on_fault) hooks_.on_fault();
  switch (outcome.transition) {
    case master::UnitAnswering::Transition::stopped_answering:
      spdlog::warn("modbus gateway: unit {} is not answering: {} forwarded requests in a row got no good answer "
                   "(the last: {}); its clients get exception 0B, the others are served as before",
                   request.unit, master::UnitAnswering::failures_to_silent, outcome_text(outcome.result));
      break;
    case master::UnitAnswering::Transition::answers_again:
      spdlog::info("modbus gateway: unit {} answers again", request.unit);
      break;
    case master::UnitAnswering::Transition::none: break;
  }
  forwarded.answer(outcome.answer);
  pump();
}

void MasterPort::answer_from_cache(Forwarded forwarded, master::Bytes answer) {
  const auto& request = forwarded.request;
  if (hooks_.on_transaction) {
    // The frames as they went on the line when the answer was kept.
    const auto query = master::rtu_frame(request.unit, request.pdu);
    const auto response = master::rtu_frame(request.unit, answer);
    hooks_.on_transaction(modbus::Transaction{modbus::PortKind::gateway, request.peer, std::chrono::system_clock::now(),
                                              TransactionState::cached, query, response, false});
  }
  answer_later(std::move(forwarded), std::move(answer));
}

void MasterPort::answer_later(Forwarded forwarded, master::Bytes answer) {
  asio::post(executor_, [forwarded = std::move(forwarded), answer = std::move(answer)] { forwarded.answer(answer); });
}

void MasterPort::refuse(Forwarded forwarded, modbus::ExceptionCode code) {
  const auto function = forwarded.request.pdu.at(0);
  answer_later(std::move(forwarded), master::gateway_exception(function, code));
}

const std::map<std::uint8_t, GatewayUnitCounters>& MasterPort::gateway_units() const {
  static const std::map<std::uint8_t, GatewayUnitCounters> none;
  return gateway_ ? gateway_->units() : none;
}

void MasterPort::take_values(const master::PlannedRequest& request, const master::MasterResponse& result,
                             Clock::time_point now) {
  const auto values = master::response_values(result.pdu, request.function, request.count);
  for (const auto index : request.blocks) {
    const auto& block = setup_.blocks[index];
    publish(block.output, master::poll_output(block, request.first, values));
    staleness_->refreshed(index, now);
  }
  stale_timer_.watch();
}

void MasterPort::publish(unsigned output, std::uint16_t value) {
  const auto it = published_.find(output);
  if (it != published_.end() && it->second == value) return;  // UnimaBUS hears changes
  published_[output] = value;
  hooks_.set_output(output, value);
}

// A good read only pushes the next expiry later, so the timer is armed once (LazyDeadline).
void MasterPort::expire_stale_values() {
  if (!running_) return;
  for (const auto i : staleness_->expire(Clock::now())) {
    const auto& block = setup_.blocks[i];
    publish(block.output, banks::not_measured);
    spdlog::warn("modbus master: {}: no good value from device {} for {} ms; output {} reads 0x7FFF", block.origin,
                 block.device, setup_.stale_after[i].count(), block.output);
  }
  stale_timer_.watch();
}

}  // namespace unima::io
