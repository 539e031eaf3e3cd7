#include "tests/sim/foreign_slave.hpp"

#include <cmath>

namespace unima::sim {

namespace {

using master::DataTable;
using master::ValueType;

Bytes exception(std::uint8_t function, std::uint8_t code) { return {static_cast<std::uint8_t>(function | 0x80), code}; }

std::uint16_t get16(std::span<const std::uint8_t> b, std::size_t at) {
  return static_cast<std::uint16_t>(b[at] << 8 | b[at + 1]);
}

}  // namespace

ForeignSlave::ForeignSlave(const master::DeviceProfile& profile) : profile_(&profile) {
  // A PLC's operand classes: every operand of a class is a cell of its table, 0 at first.
  for (const auto& c : profile.operands) {
    auto& t = table(c.table);
    for (std::uint32_t r = c.offset; r <= std::uint32_t{c.offset} + (c.last - c.first); ++r) {
      auto& cell = t[static_cast<std::uint16_t>(r)];
      cell.readable = true;
      cell.writable = !c.write_functions.empty();
    }
  }
  for (const auto& point : profile.points) {
    const auto mark = [&](std::uint8_t fn, bool reading) {
      auto& t = table(*master::table_of_function(fn));
      for (std::uint32_t r = point.reg; r < std::uint32_t{point.reg} + point.extent(); ++r) {
        auto& cell = t[static_cast<std::uint16_t>(r)];
        (reading ? cell.readable : cell.writable) = true;
      }
    };
    for (auto fn : point.read_functions) mark(fn, true);
    for (auto fn : point.write_functions) mark(fn, false);
    if (!point.example || point.length > 1) continue;
    const auto fn = point.read_functions.empty() ? point.write_functions.front() : point.read_functions.front();
    auto& t = table(*master::table_of_function(fn));
    if (point.type == ValueType::bits) {
      const auto bits = static_cast<unsigned>(*point.example);
      for (unsigned i = 0; i < point.count; ++i) t[static_cast<std::uint16_t>(point.reg + i)].value = (bits >> i) & 1u;
      continue;
    }
    std::uint16_t words[2] = {0, 0};
    master::encode_value(point.type, profile.word_order, *point.example,
                         std::span<std::uint16_t>(words, master::register_span(point.type)));
    for (unsigned i = 0; i < master::register_span(point.type); ++i)
      t[static_cast<std::uint16_t>(point.reg + i)].value = words[i];
  }
}

Bytes ForeignSlave::answer(std::span<const std::uint8_t> request) {
  if (request.empty()) return {};
  const auto fn = request[0];
  if (!profile_->implements(fn) || !master::table_of_function(fn)) return exception(fn, 0x01);
  if (fn <= 4) return read(fn, request);
  return write(fn, request);
}

Bytes ForeignSlave::read(std::uint8_t fn, std::span<const std::uint8_t> request) {
  if (request.size() != 5) return exception(fn, 0x03);
  const auto first = get16(request, 1), count = get16(request, 3);
  const bool bits = fn <= 2;
  if (count == 0 || count > (bits ? 2000 : 125)) return exception(fn, 0x03);
  const auto& t = table(*master::table_of_function(fn));
  for (std::uint32_t r = first; r < std::uint32_t{first} + count; ++r) {
    const auto cell = t.find(static_cast<std::uint16_t>(r));
    if (r > 0xFFFF || cell == t.end() || !cell->second.readable) return exception(fn, 0x02);
  }
  Bytes response{fn};
  if (bits) {
    response.push_back(static_cast<std::uint8_t>((count + 7) / 8));
    response.resize(2 + (count + 7) / 8, 0);
    for (unsigned i = 0; i < count; ++i)
      if (t.at(static_cast<std::uint16_t>(first + i)).value) response[2 + i / 8] |= static_cast<std::uint8_t>(1u << (i % 8));
  } else {
    response.push_back(static_cast<std::uint8_t>(2 * count));
    for (unsigned i = 0; i < count; ++i) {
      const auto v = t.at(static_cast<std::uint16_t>(first + i)).value;
      response.push_back(static_cast<std::uint8_t>(v >> 8));
      response.push_back(static_cast<std::uint8_t>(v & 0xFF));
    }
  }
  return response;
}

Bytes ForeignSlave::write(std::uint8_t fn, std::span<const std::uint8_t> request) {
  if (request.size() < 5) return exception(fn, 0x03);
  auto& t = table(*master::table_of_function(fn));
  const auto first = get16(request, 1);
  std::vector<std::uint16_t> values;
  if (fn == 5 || fn == 6) {
    if (request.size() != 5) return exception(fn, 0x03);
    const auto v = get16(request, 3);
    if (fn == 5 && v != 0xFF00 && v != 0x0000) return exception(fn, 0x03);
    values.push_back(fn == 5 ? (v == 0xFF00) : v);
  } else {
    const auto count = get16(request, 3);
    if (request.size() < 6) return exception(fn, 0x03);
    const std::size_t bytes = request[5];
    const std::size_t expected = fn == 15 ? (count + 7u) / 8u : 2u * count;
    if (count == 0 || count > (fn == 15 ? 1968 : 123) || bytes != expected || request.size() != 6 + bytes)
      return exception(fn, 0x03);
    for (unsigned i = 0; i < count; ++i)
      values.push_back(fn == 15 ? (request[6 + i / 8] >> (i % 8)) & 1u : get16(request, 6 + 2 * i));
  }
  for (std::uint32_t r = first; r < first + values.size(); ++r) {
    const auto cell = t.find(static_cast<std::uint16_t>(r));
    if (r > 0xFFFF || cell == t.end() || !cell->second.writable) return exception(fn, 0x02);
  }
  for (std::size_t i = 0; i < values.size(); ++i) t[static_cast<std::uint16_t>(first + i)].value = values[i];
  if (fn == 5 || fn == 6) return Bytes(request.begin(), request.end());
  return Bytes(request.begin(), request.begin() + 5);
}

std::optional<std::uint16_t> ForeignSlave::holding(std::uint16_t reg) const {
  const auto& t = table(DataTable::holding_registers);
  const auto cell = t.find(reg);
  if (cell == t.end()) return std::nullopt;
  return cell->second.value;
}

bool ForeignSlave::set_holding(std::uint16_t reg, std::uint16_t value) {
  auto& t = table(DataTable::holding_registers);
  const auto cell = t.find(reg);
  if (cell == t.end()) return false;
  cell->second.value = value;
  return true;
}

bool ForeignSlave::set_input(std::uint16_t reg, bool on) {
  auto& t = table(DataTable::discrete_inputs);
  const auto cell = t.find(reg);
  if (cell == t.end()) return false;
  cell->second.value = on;
  return true;
}

std::optional<bool> ForeignSlave::coil(std::uint16_t reg) const {
  const auto& t = table(DataTable::coils);
  const auto cell = t.find(reg);
  if (cell == t.end()) return std::nullopt;
  return cell->second.value != 0;
}

}  // namespace unima::sim
