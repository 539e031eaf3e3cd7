#pragma once
// What is wrong with a PEM file the config names (modbus.tls.*, http.tls.*, mqtt.*), said
// as a technician can act on it: no such file, not readable by this user, not a PEM
// certificate or private key (or the two swapped), a key that does not belong to its
// certificate, a certificate out of its validity. OpenSSL's own words ("system lib",
// "PEM lib") name none of this. Asked by config/host_check for every PEM file of the
// config, so `unima-bridge check`, the daemon's start and a reload say the same.

#include <ctime>
#include <optional>
#include <string>
#include <string_view>

namespace unima::tls {

enum class PemContent { certificate, private_key, ca_certificates };

/// Why `path` cannot serve as `content`, and what to do; nullopt when it can.
std::optional<std::string> pem_file_problem(const std::string& path, PemContent content);

/// Why the private key in `key_path` does not go with the certificate in `certificate_path`
/// (both usable by pem_file_problem); nullopt when it does.
/// `certificate_name` is its config key, named in the message.
std::optional<std::string> key_mismatch(const std::string& certificate_path, const std::string& key_path,
                                        std::string_view certificate_name);

/// When the (first) certificate in `path` is not valid at `now`: expired, or not yet valid.
std::optional<std::string> certificate_out_of_date(const std::string& path, std::time_t now);

}  // namespace unima::tls
