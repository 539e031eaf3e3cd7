#pragma once
// What `unima-bridge check` checks once the config is loaded (config::load_file: the parse
// and what it names on the host), as the daemon would meet it at start: the served
// register windows, the deadbands over the value model, the TLS credentials, the HTTP
// users file and that every user remote_config.http lists is in it. The CLI's `check` and
// the daemon's remote changes (SPEC §19) both call it, so both refuse the same configs
// with the same messages.

#include "config/config.hpp"

namespace unima::check {

/// Throws std::runtime_error (a config::ConfigError where the parse's positions say
/// where) whose what() names the key's file:line:column, as `check` prints it.
void check_config(const config::Config& config);

}  // namespace unima::check
