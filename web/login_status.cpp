#include "web/login_status.hpp"

namespace unima::web {

const std::vector<status::Statistic<LoginStatus>>& login_statistics() {
  using enum status::MetricType;
  using status::Samples;
  static const std::vector<status::Statistic<LoginStatus>> all{
      {"http_password_checks_total", counter, "Password hashes of http.users computed (on the worker, not the loop).",
       [](const LoginStatus& s, Samples& out) { out.add(s.checked); }},
      {"http_password_checks_in_flight", gauge, "Password checks queued or being computed.",
       [](const LoginStatus& s, Samples& out) { out.add(s.in_flight); }},
      {"http_logins_refused_total", counter,
       "Requests with a name and password refused: wrong (401), too many from one host (429), too many at once (503).",
       [](const LoginStatus& s, Samples& out) {
         out.add(s.wrong, {{"reason", "wrong"}})
             .add(s.peer_limited, {{"reason", "peer_limited"}})
             .add(s.busy, {{"reason", "busy"}});
       }},
  };
  return all;
}

}  // namespace unima::web
