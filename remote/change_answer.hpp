#pragma once
// The answer to a config sent from afar (SPEC §19), the same JSON on every channel: MQTT's
// config/result (or the MQTT 5 Response Topic), the body of HTTP's PUT /api/config, and
// `unima-bridge config apply`.
//
//   {"id": "<sha256 of the text>", "result": "applied"|"refused"|"rolled_back"|"busy",
//    "errors": [{"line": 3, "column": 5, "message": "…"}], "reason": "…",
//    "source": "mqtt"|"http"|"cli", "by": "<user or client id>"}

#include <string>
#include <string_view>
#include <vector>

namespace unima::remote {

enum class Source { mqtt, http, cli };
enum class Result { applied, refused, rolled_back, busy };

std::string_view source_name(Source source);
std::string_view result_name(Result result);

/// A config error at a line and column of the text sent.
struct ErrorAt {
  unsigned line = 0;
  unsigned column = 0;
  std::string message;
  bool operator==(const ErrorAt&) const = default;
};

struct ChangeAnswer {
  std::string id;  // sha256 of the text, lower-case hex: what the sender correlates by
  Result result = Result::refused;
  std::vector<ErrorAt> errors;
  std::string reason;
  Source source = Source::cli;
  std::string by;
};

/// The id of a config text: its sha256, lower-case hex.
std::string change_id(std::string_view text);

/// The errors of a config::ConfigError's text ("origin:line:column: message", one per
/// line), those of `origin` with their positions; any other line as a message at 0:0.
std::vector<ErrorAt> errors_at(std::string_view error_text, std::string_view origin);

/// The answer as one line of JSON.
std::string answer_json(const ChangeAnswer& answer);

}  // namespace unima::remote
