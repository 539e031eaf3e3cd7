#pragma once
// MQTT topic filters (MQTT 3.1.1 §4.7, MQTT 5 §4.7) as a config names them — which are
// filters at all, and which topics one matches — in one place for the config's check and
// for whoever decides by them at run time (mqtt/response_topic). Pure: libmosquitto's
// mosquitto_topic_matches_sub does the same for the client, but the pure libraries do not
// link it.

#include <optional>
#include <string>
#include <string_view>

namespace unima::config {

/// Why `filter` is not a topic filter the bridge takes, or nullopt when it is one: empty;
/// a NUL; `+` or `#` that is not a whole level; `#` not the last level; starting with `$`
/// (the broker's own topics, which a configured filter has no business reaching).
std::optional<std::string> topic_filter_problem(std::string_view filter);

/// Whether `topic` (a topic name, without wildcards) matches `filter` (valid by
/// topic_filter_problem): `+` is one level, `#` the level it stands in and all below it,
/// the parent too (`a/#` matches `a`); a filter starting with a wildcard never matches a
/// topic starting with `$`.
bool topic_matches_filter(std::string_view filter, std::string_view topic);

}  // namespace unima::config
