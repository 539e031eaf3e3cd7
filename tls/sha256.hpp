#pragma once
// A SHA-256 digest as lower-case hex, from OpenSSL (what `sha256sum` prints): the birth
// message names the config file it runs by this way (SPEC §15), so an operator can compare
// it with the file of a deployment tool.

#include <string>
#include <string_view>

namespace unima::tls {

/// 64 lower-case hex digits.
std::string sha256_hex(std::string_view bytes);

}  // namespace unima::tls
