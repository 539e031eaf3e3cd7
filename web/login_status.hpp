#pragma once
// The password checks of `http.users` in the status document ("http.logins", issue 29)
// and their statistics.

#include <cstdint>
#include <vector>

#include <nlohmann/json.hpp>

#include "status/statistic.hpp"

namespace unima::web {

struct LoginStatus {
  std::uint64_t checked = 0;       // hashes computed
  std::uint64_t wrong = 0;         // credentials given and refused (401)
  std::uint64_t peer_limited = 0;  // too many from one host (429)
  std::uint64_t busy = 0;          // too many at once (503)
  std::uint64_t in_flight = 0;     // queued or being computed
};

NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE_WITH_DEFAULT(LoginStatus, checked, wrong, peer_limited, busy, in_flight)

const std::vector<status::Statistic<LoginStatus>>& login_statistics();

}  // namespace unima::web
