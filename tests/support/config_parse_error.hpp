#pragma once
// What a config text is told when parsed as the file `origin` (config::parse_text on no
// host's devices): the tests of the YAML rules every config error goes through.

#include <string>

#include "config/config.hpp"
#include "tests/support/error_message.hpp"

namespace unima::test_support {

/// The ConfigError's message for `text` as `origin`, or "(no error)".
inline std::string config_parse_error(const std::string& text, const std::string& origin = "bridge.yaml") {
  return error_message<config::ConfigError>([&] { (void)config::parse_text(text, origin, config::Host{}); });
}

}  // namespace unima::test_support
