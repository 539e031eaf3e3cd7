#include "cli/master_format.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "config/master_setup.hpp"
#include "master/device_profile.hpp"
#include "master/master_plan.hpp"

namespace unima::cli {

namespace {

std::string duration_text(std::chrono::milliseconds d) {
  if (d.count() % 1000 == 0) return fmt::format("{}s", d.count() / 1000);
  return fmt::format("{}ms", d.count());
}

std::string span_text(const master::PlannedRequest& r) {
  const bool bits = r.function == 1 || r.function == 2 || r.function == 5;
  std::string text = r.count == 1 ? fmt::format("{}", r.first) : fmt::format("{}..{}", r.first, r.first + r.count - 1);
  text += fmt::format(" ({} {}{})", r.count, bits ? (r.count == 1 ? "bit" : "bits") : (r.count == 1 ? "register" : "registers"),
                      r.spans_gap ? ", spans a gap" : "");
  return text;
}

}  // namespace

std::string format_lines(const config::Config& config) {
  const auto& lines = config.modbus.lines;
  if (lines.size() < 2) return {};
  std::string out;
  for (const auto& line : lines) {
    const auto timing = config::line_timing(line.serial);
    const auto parity = config::parity_letter(line.serial.parity);
    out += fmt::format("line {}: {}, {} {} baud 8{}{}, t3.5 = {} us, ", line.name, config::line_role_name(line.role),
                       line.serial.device, line.serial.baud, parity, line.serial.stop_bits, timing.frame_gap.count());
    if (line.role == config::LineRole::slave) out += fmt::format("address {}\n", line.address);
    else out += line.gateway ? fmt::format("gateway units {}\n", config::unit_ranges_text(*line.gateway)) : "no gateway\n";
  }
  return out;
}

namespace {

// One master's plan: the line's (`line`), or modbus.master.tcp's (null).
std::string format_line_plan(const config::Config& config, const config::LineConfig* master) {
  const auto setup = config::master_setup(config, master);
  const auto plan = config::master_plan(setup);
  std::string out;
  const auto& m = config.modbus.master;
  if (!master) out += fmt::format("master: tcp {}\n", m.tcp);
  else {
    const auto& line = *master;  // "rtu" for modbus.rtu, as before lines had names
    out += fmt::format("master: {} {} {} baud, {} bits per character, t3.5 = {} us\n", line.name, line.serial.device,
                       line.serial.baud, setup.serial->bits_per_character, setup.serial->frame_gap.count());
  }
  out += fmt::format("  {} blocks in {} requests (merge_gap {})\n", setup.blocks.size(), plan.size(), m.merge_gap);
  for (std::size_t n = 0; n < plan.size(); ++n) {
    const auto& r = plan[n];
    out += fmt::format("  request {:>2}: device {:>3}, function {:>2}, {}, every {}{}\n", n + 1, r.device, r.function,
                       span_text(r), duration_text(r.period),
                       r.phase.count() ? fmt::format(" from +{:.1f}ms", static_cast<double>(r.phase.count()) / 1000) : "");
    for (const auto index : r.blocks) {
      const auto& b = setup.blocks[index];
      const auto what = b.is_read() ? fmt::format("-> output {}", b.output)
                                    : fmt::format("<- {}", setup.sources[index] ? setup.sources[index]->text : "?");
      out += fmt::format("      {} {} {} (every {}, {})\n", b.name, master::value_type_name(b.type), what,
                         duration_text(b.period), b.origin);
    }
  }
  std::vector<std::string> warnings;
  for (const auto& [device, timing] : setup.devices) {
    const double rate = master::device_request_rate(plan, device);
    const auto gap_ms = std::chrono::duration<double, std::milli>(timing.min_gap).count();
    out += fmt::format("  device {:>3}: {:.1f} requests/s, min_gap {} ms, response_timeout {} ms\n", device, rate, gap_ms,
                       std::chrono::duration_cast<std::chrono::milliseconds>(timing.response_timeout).count());
    if (gap_ms > 0 && rate > 1000.0 / gap_ms)
      warnings.push_back(fmt::format("device {} is asked {:.1f} times per second but takes at most {:.1f} (min_gap {} "
                                     "ms): its requests will come late and some will be skipped",
                                     device, rate, 1000.0 / gap_ms, gap_ms));
  }
  if (setup.serial) {
    const auto load = master::estimate_load(plan, *setup.serial);
    out += fmt::format("bus load: {:.1f} requests/s, {:.1f} % of the line at {} baud (frames and t3.5 gaps; the "
                       "slaves' reply time comes on top)\n",
                       load.requests_per_second, 100 * load.busy_fraction, setup.serial->baud);
    if (load.busy_fraction > 1)
      warnings.push_back("the plan needs more than the line can carry: requests will come late and some will be skipped");
  } else {
    double rate = 0;
    for (const auto& r : plan) rate += 1000.0 / static_cast<double>(r.period.count());
    out += fmt::format("bus load: {:.1f} requests/s\n", rate);
  }
  for (const auto& w : warnings) out += fmt::format("warning: {}\n", w);
  return out;
}

}  // namespace

std::string format_master_plan(const config::Config& config) {
  const auto lines = config.modbus.lines_of(config::LineRole::master);
  if (lines.empty()) return format_line_plan(config, nullptr);
  std::string out;
  for (const auto* line : lines) out += format_line_plan(config, line);
  return out;
}

std::string format_profiles(std::string_view id) {
  std::string out;
  if (id.empty()) {
    for (const auto& p : master::all_profiles()) {
      const auto line = p.line ? fmt::format("{} baud 8{}{}", p.line->baud, p.line->parity, p.line->stop_bits)
                               : std::string("line not given");
      const auto what = p.operands.empty() ? fmt::format("{} points", p.points.size())
                                           : fmt::format("{} operand classes", p.operands.size());
      out += fmt::format("{:<16} {} ({}): functions {}, {}, {}\n", p.id, p.name, p.source, fmt::join(p.functions, ", "),
                         line, what);
    }
    return out;
  }
  const auto* p = master::find_profile(id);
  if (!p) return out;
  out += fmt::format("{}: {} ({}), word order {}, min_gap {} us\n", p->id, p->name, p->source,
                     master::word_order_name(p->word_order), p->min_gap.count());
  if (!p->points.empty())
    out += fmt::format("{:<22} {:>5} {:<5} {:>5} {:<6} {:<6} {:>6}  {}\n", "point", "addr", "type", "count", "read",
                       "write", "scale", "unit / text");
  if (!p->operands.empty()) {
    out += fmt::format("{:<8} {:<14} {:<18} {:<6} {:<6} {:<6}  {}\n", "operand", "numbers", "table", "offset", "read",
                       "write", "text");
    for (const auto& c : p->operands)
      out += fmt::format("{:<8} {:<14} {:<18} 0x{:04X} {:<6} {:<6}  {}\n", c.name,
                         fmt::format("{}..{}", c.format(c.first), c.format(c.last)), master::data_table_name(c.table),
                         c.offset, fmt::format("{}", fmt::join(c.read_functions, ",")),
                         fmt::format("{}", fmt::join(c.write_functions, ",")), c.label);
  }
  for (const auto& pt : p->points) {
    out += fmt::format("{:<22} {:>5} {:<5} {:>5} {:<6} {:<6} {:>6}  {}{}{}\n", pt.name, pt.reg,
                       master::value_type_name(pt.type), pt.extent(), fmt::format("{}", fmt::join(pt.read_functions, ",")),
                       fmt::format("{}", fmt::join(pt.write_functions, ",")), pt.scale, pt.unit,
                       pt.unit.empty() ? "" : ", ", pt.label);
  }
  return out;
}

}  // namespace unima::cli
