#include "web/request_origin.hpp"

#include <string>

namespace unima::web {

bool from_another_site(const RequestOrigin& request) {
  if (!request.sec_fetch_site.empty())
    return request.sec_fetch_site != "same-origin" && request.sec_fetch_site != "none";
  // An older browser sends Origin alone; "null" is an opaque origin (a sandboxed frame, a
  // data: URL), never this bridge's page.
  if (request.origin.empty()) return false;
  const std::string own = std::string(request.tls ? "https://" : "http://") + std::string(request.host);
  return request.host.empty() || request.origin != own;
}

}  // namespace unima::web
