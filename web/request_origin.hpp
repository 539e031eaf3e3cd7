#pragma once
// Whether a request was sent by a browser on behalf of another site (cross-site request
// forgery). HTTP Basic credentials are sent by the browser with any request to the origin
// it learnt them for, whichever page makes it: a page elsewhere could post a form to
// POST /api/config/revert (a "simple" request, sent without CORS preflight) and the
// browser of a listed user who has the bridge's page open would authenticate it. A change
// is therefore taken only from a request that says it came from this origin, or that says
// nothing of where it came from (curl, scripts, anything that is not a browser).
//
// Browsers say it twice: Sec-Fetch-Site (Fetch Metadata; "same-origin", "same-site",
// "cross-site", "none" for a typed address) and Origin (sent with every POST and PUT by
// every current browser). Pure: the header values are handed in.

#include <string_view>

namespace unima::web {

struct RequestOrigin {
  std::string_view sec_fetch_site;  // the header's value; empty: not sent
  std::string_view origin;          // the Origin header's value; empty: not sent
  std::string_view host;            // the Host header's value (address and port the browser used)
  bool tls = false;                 // the request came over HTTPS
};

/// True when the request says it was made by a page of another origin.
bool from_another_site(const RequestOrigin& request);

}  // namespace unima::web
