#include "remote/change_answer.hpp"

#include <charconv>

#include <nlohmann/json.hpp>

#include "tls/sha256.hpp"

namespace unima::remote {

std::string_view source_name(Source source) {
  switch (source) {
    case Source::mqtt: return "mqtt";
    case Source::http: return "http";
    case Source::cli: return "cli";
  }
  return "cli";
}

std::string_view result_name(Result result) {
  switch (result) {
    case Result::applied: return "applied";
    case Result::refused: return "refused";
    case Result::rolled_back: return "rolled_back";
    case Result::busy: return "busy";
  }
  return "refused";
}

std::string change_id(std::string_view text) { return tls::sha256_hex(text); }

namespace {

// "12:5: message" after the origin: the line, the column and the rest; false when the
// text is not so.
bool split_position(std::string_view text, ErrorAt& error) {
  const auto number = [&](unsigned& value) {
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (ec != std::errc() || end == text.data() || end == text.data() + text.size() || *end != ':') return false;
    text.remove_prefix(static_cast<std::size_t>(end - text.data()) + 1);
    return true;
  };
  if (!number(error.line) || !number(error.column)) return false;
  if (text.starts_with(' ')) text.remove_prefix(1);
  error.message = std::string(text);
  return true;
}

}  // namespace

std::vector<ErrorAt> errors_at(std::string_view error_text, std::string_view origin) {
  std::vector<ErrorAt> errors;
  while (!error_text.empty()) {
    const auto end = error_text.find('\n');
    auto line = error_text.substr(0, end);
    error_text.remove_prefix(end == std::string_view::npos ? error_text.size() : end + 1);
    if (line.empty()) continue;
    ErrorAt error;
    if (line.starts_with(origin) && line.size() > origin.size() && line[origin.size()] == ':' &&
        split_position(line.substr(origin.size() + 1), error)) {
      errors.push_back(std::move(error));
      continue;
    }
    errors.push_back({0, 0, std::string(line)});
  }
  return errors;
}

std::string answer_json(const ChangeAnswer& answer) {
  auto errors = nlohmann::json::array();
  for (const auto& e : answer.errors) errors.push_back({{"line", e.line}, {"column", e.column}, {"message", e.message}});
  const nlohmann::json json = {{"id", answer.id},
                               {"result", result_name(answer.result)},
                               {"errors", std::move(errors)},
                               {"reason", answer.reason},
                               {"source", source_name(answer.source)},
                               {"by", answer.by}};
  // Replaced, not thrown: a user name or a reason is the sender's text, and an answer must go.
  return json.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

}  // namespace unima::remote
