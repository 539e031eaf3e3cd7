#include "master/gateway_cache.hpp"

#include <algorithm>

namespace unima::master {

bool GatewayCache::is_read(std::span<const std::uint8_t> request_pdu) {
  return !request_pdu.empty() && request_pdu[0] >= 1 && request_pdu[0] <= 4;
}

std::optional<GatewayCache::Bytes> GatewayCache::answer(std::uint8_t unit, std::span<const std::uint8_t> request_pdu,
                                                        TimePoint now) {
  if (!is_read(request_pdu)) return std::nullopt;
  forget_expired(now);
  for (const auto& e : entries_)
    if (e.unit == unit && std::ranges::equal(e.request, request_pdu)) return e.answer;
  return std::nullopt;
}

void GatewayCache::answered(std::uint8_t unit, std::span<const std::uint8_t> request_pdu,
                            std::span<const std::uint8_t> answer_pdu, TimePoint now) {
  if (window_ <= Duration::zero() || per_unit_ == 0 || total_ == 0) return;
  if (!is_read(request_pdu) || answer_pdu.empty() || (answer_pdu[0] & 0x80) != 0) return;
  forget_expired(now);
  // The newer answer replaces an older one to the same read.
  for (auto it = entries_.begin(); it != entries_.end(); ++it)
    if (it->unit == unit && std::ranges::equal(it->request, request_pdu)) {
      erase(it);
      break;
    }
  if (per_unit_count_[unit] >= per_unit_) {
    const auto oldest = std::ranges::find_if(entries_, [&](const Entry& e) { return e.unit == unit; });
    if (oldest != entries_.end()) erase(oldest);
  }
  if (entries_.size() >= total_) erase(entries_.begin());
  entries_.push_back(Entry{unit, Bytes(request_pdu.begin(), request_pdu.end()), Bytes(answer_pdu.begin(), answer_pdu.end()), now});
  ++per_unit_count_[unit];
}

void GatewayCache::written(std::uint8_t unit) {
  for (auto it = entries_.begin(); it != entries_.end();) it = it->unit == unit ? erase(it) : std::next(it);
}

// Answers come in time order, so the expired ones are the first.
void GatewayCache::forget_expired(TimePoint now) {
  while (!entries_.empty() && now - entries_.front().answered >= window_) erase(entries_.begin());
}

std::deque<GatewayCache::Entry>::iterator GatewayCache::erase(std::deque<Entry>::iterator it) {
  --per_unit_count_[it->unit];
  return entries_.erase(it);
}

}  // namespace unima::master
