#include "master/master_plan.hpp"

#include <algorithm>
#include <limits>
#include <map>
#include <numeric>
#include <tuple>

#include "modbus/protocol.hpp"
#include "modbus/rtu/rtu_frame_length.hpp"

namespace unima::master {

bool PlannedRequest::is_read() const { return function <= modbus::function::read_input_registers; }

namespace {

bool bit_function(std::uint8_t fn) { return fn == modbus::function::read_coils || fn == modbus::function::read_discrete_inputs; }

// Reads of one device and function, by address, merged while the next block starts at most
// `gap` past the end of the request and the request stays within the function's maximum.
void merge_group(std::vector<std::size_t> indices, std::span<const MasterBlock> blocks, unsigned gap,
                 std::uint16_t max_count, std::vector<PlannedRequest>& out) {
  std::stable_sort(indices.begin(), indices.end(), [&](std::size_t a, std::size_t b) {
    return std::tie(blocks[a].reg, blocks[a].count) < std::tie(blocks[b].reg, blocks[b].count);
  });
  PlannedRequest current;
  std::uint32_t end = 0;
  bool open = false;
  const auto close = [&] {
    if (!open) return;
    current.count = static_cast<std::uint16_t>(end - current.first);
    out.push_back(current);
    open = false;
  };
  for (std::size_t index : indices) {
    const auto& b = blocks[index];
    const bool fits = open && b.reg <= end + gap && std::max(end, b.end()) - current.first <= max_count;
    if (!fits) {
      close();
      current = PlannedRequest{};
      current.device = b.device;
      current.function = b.function;
      current.first = b.reg;
      current.period = b.period;
      end = b.end();
      open = true;
    } else {
      if (b.reg > end) current.spans_gap = true;
      end = std::max(end, b.end());
      current.period = std::min(current.period, b.period);
    }
    current.blocks.push_back(index);
  }
  close();
}

}  // namespace

namespace {
// The request of one block alone.
PlannedRequest request_of(const MasterBlock& b, std::size_t index) {
  PlannedRequest request;
  request.device = b.device;
  request.function = b.function;
  request.first = b.reg;
  request.count = b.count;
  request.period = b.period;
  request.blocks = {index};
  return request;
}
}  // namespace

std::vector<PlannedRequest> plan_requests(std::span<const MasterBlock> blocks, const PlanOptions& options) {
  std::map<std::pair<std::uint8_t, std::uint8_t>, std::vector<std::size_t>> reads;
  std::vector<PlannedRequest> planned;
  for (std::size_t i = 0; i < blocks.size(); ++i) {
    const auto& b = blocks[i];
    if (b.is_read()) {
      reads[{b.device, b.function}].push_back(i);
    } else {
      planned.push_back(request_of(b, i));
    }
  }
  for (auto& [key, indices] : reads) {
    const auto max_count = bit_function(key.second) ? options.max_read_bits : options.max_read_registers;
    merge_group(std::move(indices), blocks, options.merge_gap, max_count, planned);
  }
  std::stable_sort(planned.begin(), planned.end(), [](const PlannedRequest& a, const PlannedRequest& b) {
    return std::make_tuple(a.device, !a.is_read(), a.first, a.function) <
           std::make_tuple(b.device, !b.is_read(), b.first, b.function);
  });
  return planned;
}

std::vector<PlannedRequest> split_request(const PlannedRequest& request, std::span<const MasterBlock> blocks) {
  std::vector<PlannedRequest> parts;
  if (request.spans_gap) {
    const auto max_count = static_cast<std::uint16_t>(request.count);
    merge_group(request.blocks, blocks, 0, max_count, parts);
    return parts;
  }
  // Gap-free already: one request per distinct range, so that one bad block cannot take
  // its neighbours down with it.
  std::vector<std::size_t> indices = request.blocks;
  for (std::size_t index : indices) {
    const auto& b = blocks[index];
    auto same = std::find_if(parts.begin(), parts.end(),
                             [&](const PlannedRequest& p) { return p.first == b.reg && p.count == b.count; });
    if (same != parts.end()) {
      same->blocks.push_back(index);
      same->period = std::min(same->period, b.period);
      continue;
    }
    parts.push_back(request_of(b, index));
  }
  if (parts.size() <= 1) parts.clear();
  return parts;
}

std::size_t rtu_request_size(const PlannedRequest& r) { return modbus::rtu_request_size(r.function, r.count); }
std::size_t rtu_response_size(const PlannedRequest& r) { return modbus::rtu_response_size(r.function, r.count); }

BusLoad estimate_load(std::span<const PlannedRequest> requests, const modbus::RtuTiming& line) {
  BusLoad load;
  const double char_s = static_cast<double>(line.bits_per_character) / line.baud;
  const double silence_s = std::chrono::duration<double>(line.frame_gap).count();
  for (const auto& r : requests) {
    const double rate = 1000.0 / static_cast<double>(r.period.count());
    const double busy = static_cast<double>(rtu_request_size(r) + rtu_response_size(r)) * char_s + 2 * silence_s;
    load.requests_per_second += rate;
    load.busy_fraction += rate * busy;
  }
  return load;
}

double device_request_rate(std::span<const PlannedRequest> requests, std::uint8_t device) {
  double rate = 0;
  for (const auto& r : requests)
    if (r.device == device) rate += 1000.0 / static_cast<double>(r.period.count());
  return rate;
}

}  // namespace unima::master

namespace unima::master {

std::chrono::microseconds transaction_estimate(const PlannedRequest& request, const std::optional<modbus::RtuTiming>& line,
                                               std::chrono::microseconds tcp_slot) {
  if (!line) return tcp_slot;
  const auto bytes = static_cast<long>(rtu_request_size(request) + rtu_response_size(request));
  return line->character * bytes + 2 * line->frame_gap;
}

void assign_phases(std::vector<PlannedRequest>& requests, std::span<const std::chrono::microseconds> slots,
                   const std::map<std::uint8_t, std::chrono::microseconds>& min_gaps) {
  using std::chrono::microseconds;
  // Microseconds as the count chrono keeps them in: 64 bits everywhere, where `long` is 32
  // bits on armhf and a period of more than 35 minutes would not fit.
  using Micros = microseconds::rep;
  std::vector<std::size_t> order(requests.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return requests[a].period < requests[b].period; });
  constexpr Micros step = 500;                 // µs between the offsets tried
  constexpr Micros longest_search = 2'000'000; // µs: phases beyond two seconds buy nothing
  std::vector<std::size_t> placed;
  for (const auto i : order) {
    const Micros period = std::chrono::duration_cast<microseconds>(requests[i].period).count();
    const Micros limit = std::min(period, longest_search);
    Micros best = 0;
    double best_score = -1;
    for (Micros offset = 0; offset < limit; offset += step) {
      double score = std::numeric_limits<double>::infinity();
      for (const auto j : placed) {
        const Micros other = std::chrono::duration_cast<microseconds>(requests[j].period).count();
        const Micros circle = std::gcd(period, other);
        Micros distance = (offset - requests[j].phase.count()) % circle;
        if (distance < 0) distance += circle;
        distance = std::min(distance, circle - distance);
        Micros need = std::max(slots[i].count(), slots[j].count());
        if (requests[i].device == requests[j].device) {
          const auto gap = min_gaps.find(requests[i].device);
          if (gap != min_gaps.end()) need = std::max(need, gap->second.count());
        }
        score = std::min(score, static_cast<double>(distance) / static_cast<double>(std::max(need, Micros{1})));
      }
      if (score > best_score) {
        best_score = score;
        best = offset;
      }
      if (score >= 1) break;  // first fit: the earliest offset that keeps clear of all others
    }
    requests[i].phase = microseconds(best);
    placed.push_back(i);
  }
}

}  // namespace unima::master
