#include "io/master/master_port.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "io/master/master_rtu_link.hpp"
#include "io/master/master_tcp_link.hpp"
#include "master/master_codec.hpp"

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

std::string_view state_name(TransactionState state) {
  switch (state) {
    case TransactionState::done: return "Done";
    case TransactionState::not_for_me: return "Not4Me";
    case TransactionState::err01: return "Err01";
    case TransactionState::err02: return "Err02";
    case TransactionState::err03: return "Err03";
    case TransactionState::err04: return "Err04";
    case TransactionState::timeout: return "Timeout";
  }
  return "?";
}

std::string range(const master::PlannedRequest& r) {
  return r.count == 1 ? fmt::format("{}", r.first) : fmt::format("{}..{}", r.first, r.first + r.count - 1);
}

std::string outcome_text(const master::MasterResponse& r) {
  if (r.status != ResponseStatus::exception) return std::string(response_status_name(r.status));
  return fmt::format("exception {:02X}", static_cast<unsigned>(r.exception));
}

}  // namespace

std::string describe_master_transaction(const modbus::Transaction& t) {
  return fmt::format("{} {}{} {} -> {}", state_name(t.state), t.peer.empty() ? "rtu" : "tcp:", t.peer, hex(t.query),
                     hex(t.response));
}

std::shared_ptr<MasterPort> MasterPort::create(asio::io_context& io, const config::Config& config, Hooks hooks) {
  auto setup = config::master_setup(config);
  std::shared_ptr<MasterLink> link;
  if (const auto& master = config.modbus.master; !master.tcp.empty())
    link = std::make_shared<MasterTcpLink>(io, master.tcp, master.tcp_target);
  else
    link = std::make_shared<MasterRtuLink>(io, *config.modbus.rtu);
  return std::make_shared<MasterPort>(io, std::move(setup), std::move(link), std::move(hooks));
}

MasterPort::MasterPort(asio::io_context& io, config::MasterSetup setup, std::shared_ptr<MasterLink> link, Hooks hooks)
    : setup_(std::move(setup)),
      link_(std::move(link)),
      hooks_(std::move(hooks)),
      wake_timer_(io),
      stale_timer_(io.get_executor(), [this] { return staleness_ ? staleness_->next_expiry() : std::nullopt; },
                   [this] { expire_stale_values(); }) {}

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
  spdlog::info("modbus master: {}, {} requests for {} blocks", link_->describe(), scheduler_->request_count(),
               setup_.blocks.size());
  stale_timer_.watch();
  pump();
}

void MasterPort::stop() {
  if (!running_) return;
  running_ = false;
  link_->close();
  wake_timer_.cancel();
  stale_timer_.cancel();
  in_flight_ = false;
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
    if (decision.send) {
      send(*decision.send);
      continue;
    }
    if (decision.wake == Clock::time_point::max()) return;
    wake_timer_.expires_at(decision.wake);
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
  in_flight_ = true;
  const auto sent = std::chrono::system_clock::now();
  if (hooks_.on_query_sent) hooks_.on_query_sent(sent);
  // A frame to a device in doubt may wait less than its time-out: only as long as the line
  // has room before the next request of a live device.
  const auto wait = choice.timeout > MasterScheduler::Duration::zero() ? choice.timeout
                                                                       : scheduler_->timing(request.device).response_timeout;
  const auto timeout = std::chrono::duration_cast<std::chrono::milliseconds>(wait);
  link_->transact(request.device, pdu, timeout,
                  [weak = weak_from_this(), choice, pdu, sent](master::Bytes query, master::Bytes response) {
                    if (const auto self = weak.lock())
                      self->finished(choice, pdu, sent, std::move(query), std::move(response));
                  });
}

void MasterPort::finished(const MasterScheduler::Choice& choice, const master::Bytes& pdu,
                          std::chrono::system_clock::time_point sent, master::Bytes query, master::Bytes response) {
  if (!running_) return;
  in_flight_ = false;
  const auto now = Clock::now();
  const auto request = scheduler_->request(choice.request);  // a copy: replace() below may move it
  const auto result = link_->check(response, request.device, pdu);
  const auto state = master::transaction_state(result);
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
  if (state != TransactionState::done && hooks_.on_fault) hooks_.on_fault();

  if (result.status == ResponseStatus::ok && request.is_read()) take_values(request, result, now);
  if (auto parts = master::split_after(request, result, setup_.blocks); !parts.empty()) {
    spdlog::warn("modbus master: device {} answered exception 02 to function {} {}; reading it in {} requests "
                 "from now on",
                 request.device, request.function, range(request), parts.size());
    scheduler_->replace(choice.request, std::move(parts));
  }
  const auto outcome = master::slave_answered(result) ? MasterScheduler::Outcome::answered : MasterScheduler::Outcome::failed;
  switch (scheduler_->end(choice, outcome, now)) {
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
