#include "monitor/monitor_line.hpp"

#include <array>
#include <charconv>
#include <cstring>
#include <variant>

#include <nlohmann/json.hpp>

#include "monitor/hex_text.hpp"
#include "platform/json_text.hpp"
#include "platform/log_text.hpp"
#include "platform/utc_time.hpp"

namespace unima::monitor {

namespace {

using Clock = std::chrono::system_clock;

constexpr std::array<std::string_view, 8> state_names = {"Done",  "Not4Me", "Err01",   "Err02",
                                                         "Err03", "Err04",  "Timeout", "Cached"};
// Writes a line through a raw pointer into space reserved for its bound, so that no
// character is checked against a capacity: the writer thread formats one line per
// transaction, and per-character appends were most of its cost. The loops work on a
// local copy of the pointer: a store through a char pointer may alias the member, which
// would make the compiler reload it after every character.
class LineWriter {
 public:
  explicit LineWriter(char* out) : p_(out) {}
  LineWriter(const LineWriter&) = delete;
  LineWriter& operator=(const LineWriter&) = delete;
  char* end() const { return p_; }

  void put(char c) { *p_++ = c; }
  void put(std::string_view text) {
    std::memcpy(p_, text.data(), text.size());
    p_ += text.size();
  }
  void hex_byte(std::uint8_t byte) { p_ = write_hex_digits(p_, byte); }
  void hex16(std::uint16_t value) {
    hex_byte(static_cast<std::uint8_t>(value >> 8));
    hex_byte(static_cast<std::uint8_t>(value));
  }
  // "04 00 11", or "-" for nothing. The bound leaves room for the last cell's spare byte.
  void hex_bytes(std::span<const std::uint8_t> bytes) {
    if (bytes.empty()) {
      put('-');
      return;
    }
    p_ = write_hex_cells(p_, bytes.data(), bytes.size()) - 1;  // no space after the last byte
  }
  void decimal(std::uint64_t value) { p_ = std::to_chars(p_, p_ + 20, value).ptr; }
  // A field of a text line is one word, and a port name is the peer's text (a TLS
  // client's certificate names its role): a control character or a space in it is escaped
  // as in the log (platform/log_text), so a peer can neither forge a line nor shift the
  // fields after its name. monitor_line_bound's room for the port (6 bytes a character,
  // for JSON's \u00XX) holds these escapes (4 at most) too.
  void word(std::string_view text) {
    char* p = p_;
    for (const char c : text) {
      const auto byte = static_cast<unsigned char>(c);
      if (byte == ' ' || platform::is_control(byte)) p = platform::escape_byte(p, byte);
      else *p++ = c;
    }
    p_ = p;
  }
  // Hex strings never hold characters JSON must escape, but a port name is the peer's
  // text, so escaping keeps a line valid and on one line whatever it holds.
  void json_string(std::string_view text) {
    put('"');
    for (const char c : text) {
      if (c == '"' || c == '\\') {
        put('\\');
        put(c);
      } else if (platform::is_control(static_cast<unsigned char>(c))) {
        put("\\u00");
        hex_byte(static_cast<std::uint8_t>(c));
      } else {
        put(c);
      }
    }
    put('"');
  }
  void utc_time(Clock::time_point time) { p_ = platform::write_utc_time(p_, time); }

 private:
  char* p_;
};

// Appends what `write` writes into `bound` bytes of room at the end of `out`.
template <typename Write>
void append_bounded(std::string& out, std::size_t bound, Write&& write) {
  const auto start = out.size();
  out.resize(start + bound);
  LineWriter w(out.data() + start);
  write(w);
  out.resize(static_cast<std::size_t>(w.end() - out.data()));
}

void write_text(LineWriter& w, const MonitorFields& f) {
  w.utc_time(f.time);
  w.put(' ');
  w.word(f.port);
  w.put(" Ix=");
  w.decimal(f.ix);
  w.put(" Rc=");
  w.decimal(f.rc);
  w.put(" State=");
  w.put(state_name(f.state));
  if (f.query.mbap) {
    w.put(" TrID=");
    w.hex16(f.query.mbap->transaction_id);
    w.put(" PtID=");
    w.hex16(f.query.mbap->protocol_id);
    w.put(" Len=");
    w.hex16(f.query.mbap->length);
  }
  w.put(" Ad=");
  if (f.query.address) w.decimal(*f.query.address);
  else w.put('-');
  w.put(" PDU=");
  w.hex_bytes(f.query.pdu);
  if (f.query.crc_on_wire) {
    w.put(" CRC=");
    w.hex16(*f.query.crc_on_wire);
  }
  w.put(" Response=");
  w.hex_bytes(f.response);
  w.put('\n');
}

void write_json(LineWriter& w, const MonitorFields& f) {
  w.put("{\"time\":\"");
  w.utc_time(f.time);
  w.put("\",\"port\":");
  w.json_string(f.port);
  w.put(",\"ix\":");
  w.decimal(f.ix);
  w.put(",\"rc\":");
  w.decimal(f.rc);
  w.put(",\"state\":\"");
  w.put(state_name(f.state));
  w.put('"');
  if (f.query.mbap) {
    w.put(",\"trid\":");
    w.decimal(f.query.mbap->transaction_id);
    w.put(",\"ptid\":");
    w.decimal(f.query.mbap->protocol_id);
    w.put(",\"len\":");
    w.decimal(f.query.mbap->length);
  }
  w.put(",\"ad\":");
  if (f.query.address) w.decimal(*f.query.address);
  else w.put("null");
  w.put(",\"pdu\":");
  if (f.query.pdu.empty()) {
    w.put("null");
  } else {
    w.put('"');
    w.hex_bytes(f.query.pdu);
    w.put('"');
  }
  if (f.query.crc_on_wire) {
    w.put(",\"crc\":\"");
    w.hex16(*f.query.crc_on_wire);
    w.put('"');
  }
  w.put(",\"response\":");
  if (f.response.empty()) {
    w.put("null");
  } else {
    w.put('"');
    w.hex_bytes(f.response);
    w.put('"');
  }
  w.put("}\n");
}

void write_line(LineWriter& w, const MonitorFields& f, MonitorFormat format) {
  if (format == MonitorFormat::json) write_json(w, f);
  else write_text(w, f);
}

void write_drop_notice(LineWriter& w, Clock::time_point time, std::uint64_t dropped, MonitorFormat format) {
  if (format == MonitorFormat::json) {
    w.put("{\"time\":\"");
    w.utc_time(time);
    w.put("\",\"port\":\"monitor\",\"dropped\":");
    w.decimal(dropped);
    w.put("}\n");
  } else {
    w.utc_time(time);
    w.put(" monitor Dropped=");
    w.decimal(dropped);
    w.put('\n');
  }
}

std::optional<std::uint64_t> parse_unsigned(std::string_view text, int base, std::uint64_t max) {
  std::uint64_t value = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value, base);
  if (text.empty() || ec != std::errc{} || end != text.data() + text.size() || value > max) return std::nullopt;
  return value;
}

std::optional<std::uint8_t> parse_hex_byte(std::string_view text) {
  if (text.size() != 2) return std::nullopt;
  const auto value = parse_unsigned(text, 16, 0xFF);
  if (!value) return std::nullopt;
  return static_cast<std::uint8_t>(*value);
}

std::optional<std::uint16_t> parse_hex16(std::string_view text) {
  if (text.size() != 4) return std::nullopt;
  const auto value = parse_unsigned(text, 16, 0xFFFF);
  if (!value) return std::nullopt;
  return static_cast<std::uint16_t>(*value);
}

// "04 00 11" or "-"
std::optional<std::vector<std::uint8_t>> parse_hex_bytes(std::string_view text) {
  std::vector<std::uint8_t> bytes;
  if (text == "-") return bytes;
  while (!text.empty()) {
    const auto space = text.find(' ');
    const auto byte = parse_hex_byte(text.substr(0, space));
    if (!byte) return std::nullopt;
    bytes.push_back(*byte);
    if (space == std::string_view::npos) break;
    text.remove_prefix(space + 1);
  }
  if (bytes.empty()) return std::nullopt;
  return bytes;
}

std::string_view trim_newline(std::string_view line) {
  while (!line.empty() && (line.back() == '\n' || line.back() == '\r')) line.remove_suffix(1);
  return line;
}

// Splits "key=value": the value of PDU and Response runs over the following byte tokens.
class TextReader {
 public:
  explicit TextReader(std::string_view line) : rest_(line) {}

  std::string_view word() {
    const auto space = rest_.find(' ');
    const auto word = rest_.substr(0, space);
    rest_ = space == std::string_view::npos ? std::string_view{} : rest_.substr(space + 1);
    return word;
  }
  bool done() const { return rest_.empty(); }
  // After "KEY=", the value up to the next "KEY=" token (or the end of the line).
  std::string_view value_until_next_key(std::string_view first) {
    const char* begin = first.data();
    std::size_t length = first.size();
    while (!rest_.empty()) {
      const auto space = rest_.find(' ');
      const auto next = rest_.substr(0, space);
      if (next.find('=') != std::string_view::npos) break;
      length = static_cast<std::size_t>(next.data() + next.size() - begin);
      rest_ = space == std::string_view::npos ? std::string_view{} : rest_.substr(space + 1);
    }
    return {begin, length};
  }

 private:
  std::string_view rest_;
};

std::optional<MonitorLine> parse_text(std::string_view text) {
  TextReader reader(text);
  MonitorLine line;
  const auto time = platform::parse_utc_time(reader.word());
  if (!time) return std::nullopt;
  line.time = *time;
  line.port = std::string(reader.word());
  if (line.port.empty()) return std::nullopt;
  bool has_ix = false, has_rc = false, has_state = false, has_ad = false, has_pdu = false, has_response = false;
  std::optional<std::uint16_t> trid, ptid, len;
  while (!reader.done()) {
    const auto word = reader.word();
    const auto equals = word.find('=');
    if (equals == std::string_view::npos) return std::nullopt;
    const auto key = word.substr(0, equals);
    const auto value = word.substr(equals + 1);
    if (key == "Dropped") {
      const auto n = parse_unsigned(value, 10, UINT64_MAX);
      if (!n || line.port != "monitor" || !reader.done()) return std::nullopt;
      line.kind = MonitorLine::Kind::drop_notice;
      line.dropped = *n;
      return line;
    } else if (key == "Ix") {
      const auto n = parse_unsigned(value, 10, 255);
      if (!n) return std::nullopt;
      line.ix = static_cast<std::uint8_t>(*n);
      has_ix = true;
    } else if (key == "Rc") {
      const auto n = parse_unsigned(value, 10, 1'000'000);
      if (!n) return std::nullopt;
      line.rc = static_cast<std::size_t>(*n);
      has_rc = true;
    } else if (key == "State") {
      const auto state = parse_state(value);
      if (!state) return std::nullopt;
      line.state = *state;
      has_state = true;
    } else if (key == "TrID") {
      if (!(trid = parse_hex16(value))) return std::nullopt;
    } else if (key == "PtID") {
      if (!(ptid = parse_hex16(value))) return std::nullopt;
    } else if (key == "Len") {
      if (!(len = parse_hex16(value))) return std::nullopt;
    } else if (key == "Ad") {
      if (value != "-") {
        const auto n = parse_unsigned(value, 10, 255);
        if (!n) return std::nullopt;
        line.address = static_cast<std::uint8_t>(*n);
      }
      has_ad = true;
    } else if (key == "PDU") {
      auto bytes = parse_hex_bytes(reader.value_until_next_key(value));
      if (!bytes) return std::nullopt;
      line.pdu = std::move(*bytes);
      has_pdu = true;
    } else if (key == "CRC") {
      if (!(line.crc_on_wire = parse_hex16(value))) return std::nullopt;
    } else if (key == "Response") {
      auto bytes = parse_hex_bytes(reader.value_until_next_key(value));
      if (!bytes || !reader.done()) return std::nullopt;
      line.response = std::move(*bytes);
      has_response = true;
    } else {
      return std::nullopt;
    }
  }
  if (!(has_ix && has_rc && has_state && has_ad && has_pdu && has_response)) return std::nullopt;
  if (trid || ptid || len) {
    if (!(trid && ptid && len)) return std::nullopt;
    line.mbap = modbus::MbapHeader{*trid, *ptid, *len, line.address.value_or(0)};
  }
  return line;
}

std::optional<MonitorLine> parse_json(std::string_view text) {
  const auto parsed = platform::parse_json_text(text);
  const auto* value = std::get_if<nlohmann::json>(&parsed);
  if (!value || !value->is_object()) return std::nullopt;
  const auto& object = *value;
  const auto string_at = [&](const char* key) -> std::optional<std::string> {
    const auto it = object.find(key);
    if (it == object.end() || !it->is_string()) return std::nullopt;
    return it->get<std::string>();
  };
  const auto number_at = [&](const char* key, std::uint64_t max) -> std::optional<std::uint64_t> {
    const auto it = object.find(key);
    if (it == object.end() || !it->is_number_unsigned()) return std::nullopt;
    const auto value = it->get<std::uint64_t>();
    if (value > max) return std::nullopt;
    return value;
  };
  // A hex string, or null for "-"; nullopt when it is neither.
  const auto bytes_at = [&](const char* key) -> std::optional<std::vector<std::uint8_t>> {
    const auto it = object.find(key);
    if (it == object.end()) return std::nullopt;
    if (it->is_null()) return std::vector<std::uint8_t>{};
    if (!it->is_string()) return std::nullopt;
    const auto text = it->get<std::string>();
    if (text == "-") return std::nullopt;
    return parse_hex_bytes(text);
  };

  MonitorLine line;
  const auto time = string_at("time");
  const auto port = string_at("port");
  if (!time || !port) return std::nullopt;
  const auto parsed_time = platform::parse_utc_time(*time);
  if (!parsed_time) return std::nullopt;
  line.time = *parsed_time;
  line.port = *port;
  if (object.contains("dropped")) {
    const auto dropped = number_at("dropped", UINT64_MAX);
    if (!dropped) return std::nullopt;
    line.kind = MonitorLine::Kind::drop_notice;
    line.dropped = *dropped;
    return line;
  }
  const auto ix = number_at("ix", 255);
  const auto rc = number_at("rc", 1'000'000);
  const auto state_text = string_at("state");
  const auto state = state_text ? parse_state(*state_text) : std::nullopt;
  auto pdu = bytes_at("pdu");
  auto response = bytes_at("response");
  if (!ix || !rc || !state || !pdu || !response) return std::nullopt;
  line.ix = static_cast<std::uint8_t>(*ix);
  line.rc = static_cast<std::size_t>(*rc);
  line.state = *state;
  line.pdu = std::move(*pdu);
  line.response = std::move(*response);
  if (const auto it = object.find("ad"); it != object.end() && !it->is_null()) {
    const auto ad = number_at("ad", 255);
    if (!ad) return std::nullopt;
    line.address = static_cast<std::uint8_t>(*ad);
  }
  if (object.contains("trid") || object.contains("ptid") || object.contains("len")) {
    const auto trid = number_at("trid", 0xFFFF), ptid = number_at("ptid", 0xFFFF), len = number_at("len", 0xFFFF);
    if (!trid || !ptid || !len) return std::nullopt;
    line.mbap = modbus::MbapHeader{static_cast<std::uint16_t>(*trid), static_cast<std::uint16_t>(*ptid),
                           static_cast<std::uint16_t>(*len), line.address.value_or(0)};
  }
  if (object.contains("crc")) {
    const auto crc = string_at("crc");
    if (!crc || !(line.crc_on_wire = parse_hex16(*crc))) return std::nullopt;
  }
  return line;
}

}  // namespace

std::string_view state_name(modbus::TransactionState state) { return state_names[static_cast<std::size_t>(state)]; }

std::optional<modbus::TransactionState> parse_state(std::string_view name) {
  for (std::size_t i = 0; i < state_names.size(); ++i)
    if (state_names[i] == name) return static_cast<modbus::TransactionState>(i);
  return std::nullopt;
}

void append_port_name(std::string& out, modbus::PortKind port, std::string_view peer, std::string_view line) {
  const auto named = [&](const char* kind) {
    out += kind;
    if (line.empty()) return;
    out += ':';
    out += line;
  };
  switch (port) {
    case modbus::PortKind::tcp:
      out += "tcp:";
      out += peer;
      return;
    case modbus::PortKind::tls:  // the peer names the client's role (or subject) and address
      out += "tls:";
      out += peer;
      return;
    case modbus::PortKind::rtu: named("rtu"); return;
    case modbus::PortKind::master: named("master"); return;
    case modbus::PortKind::gateway:  // the client whose request went on the line
      named("gw");
      out += ':';
      out += peer;
      return;
  }
}

MonitorFields monitor_fields(const modbus::Transaction& transaction, std::uint8_t ix, std::string_view port_name) {
  MonitorFields fields;
  fields.time = transaction.time;
  fields.port = port_name;
  fields.ix = ix;
  fields.rc = transaction.query.size();
  fields.state = transaction.state;
  fields.query = modbus::view_adu(transaction.query, modbus::framing_of(transaction));
  fields.response = transaction.response;
  return fields;
}

std::size_t monitor_line_bound(const MonitorFields& f) {
  // Fixed text, the port escaped at worst, three characters a byte (and a cell's spare byte).
  return 256 + 6 * f.port.size() + 3 * (f.query.pdu.size() + f.response.size()) + 2;
}

char* write_monitor_line(char* out, const MonitorFields& fields, MonitorFormat format) {
  LineWriter w(out);
  write_line(w, fields, format);
  return w.end();
}

void append_monitor_line(std::string& out, const MonitorFields& fields, MonitorFormat format) {
  append_bounded(out, monitor_line_bound(fields), [&](LineWriter& w) { write_line(w, fields, format); });
}

void append_drop_notice(std::string& out, Clock::time_point time, std::uint64_t dropped, MonitorFormat format) {
  append_bounded(out, 128, [&](LineWriter& w) { write_drop_notice(w, time, dropped, format); });
}

MonitorFields MonitorLine::fields() const {
  MonitorFields f;
  f.time = time;
  f.port = port;
  f.ix = ix;
  f.rc = rc;
  f.state = state;
  f.query.mbap = mbap;
  f.query.address = address;
  f.query.pdu = pdu;
  f.query.crc_on_wire = crc_on_wire;
  f.response = response;
  return f;
}

std::optional<MonitorLine> parse_monitor_line(std::string_view line) {
  line = trim_newline(line);
  if (line.empty()) return std::nullopt;
  if (line.front() == '{') return parse_json(line);
  return parse_text(line);
}

}  // namespace unima::monitor
