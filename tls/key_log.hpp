#pragma once
// OpenSSL 3.0 tells a connection's TLS 1.3 traffic secrets only to a key-log callback, as
// lines of the NSS key-log format: "LABEL <client random> <secret>", both in hex. Shared
// by the port's session (tls/memory_session) and the benchmark's client.

#include <cstdint>
#include <string_view>
#include <vector>

namespace unima::tls {

/// If `line` is `label`'s, its secret into `secret` (reserved first, so no reallocation
/// leaves a copy behind) and true; false otherwise, or if its hex is broken (then `secret`
/// is left empty).
bool read_key_log_secret(std::string_view line, std::string_view label, std::vector<std::uint8_t>& secret);

}  // namespace unima::tls
