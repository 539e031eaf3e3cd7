#pragma once
// The bridge's default MQTT identity (SPEC §15): `unima-bridge-<hostname>-<the first 8 hex
// digits of /etc/machine-id>`, so that two bridges of one cloned image (the same host name)
// never share a client id — a broker lets only one session have an id, and two bridges
// with one would take it from each other. Pure: the host's name and machine id are handed
// in (config::Host reads them once).

#include <string>
#include <string_view>

namespace unima::config {

/// The first 8 hex digits (lower case) of a machine id as machine-id(5) writes it (32 hex
/// digits, a newline); empty when `text` is not one. Only these are ever published: the
/// whole id "should be considered confidential" (machine-id(5)) and 8 digits tell a fleet's
/// bridges apart well enough (two of 10,000 sites share them with odds of about 1 in 86,000).
std::string machine_id_digits(std::string_view text);

/// The default client id: with `machine_id_digits` (machine_id_digits's result)
/// `unima-bridge-<host>-<digits>`, without `unima-bridge-<host>`, and `unima-bridge` alone
/// for a host without a name. Host names long enough to take the id past 64 characters
/// (the limit mqtt.client_id keeps) are cut short: the machine id still tells them apart.
std::string default_client_id(std::string_view host_name, std::string_view machine_id_digits);

/// machine-id(5)'s file, read once at config time.
inline constexpr std::string_view machine_id_file = "/etc/machine-id";

}  // namespace unima::config
