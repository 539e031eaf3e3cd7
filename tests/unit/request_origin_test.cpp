// Whether a request was made by another site's page (web/request_origin): the rule that
// keeps a browser from being made to change the config for a page elsewhere.

#include "web/request_origin.hpp"

#include <gtest/gtest.h>

namespace unima {
namespace {

using web::from_another_site;

TEST(RequestOrigin, AClientThatIsNoBrowserSaysNothingAndIsTaken) {
  EXPECT_FALSE(from_another_site({.sec_fetch_site = "", .origin = "", .host = "127.0.0.1:8443", .tls = true}));
}

TEST(RequestOrigin, FetchMetadataDecidesWhenABrowserSendsIt) {
  EXPECT_FALSE(from_another_site({.sec_fetch_site = "same-origin", .origin = "https://bridge:8443", .host = "bridge:8443", .tls = true}));
  EXPECT_FALSE(from_another_site({.sec_fetch_site = "none", .origin = "", .host = "bridge:8443", .tls = true}));
  EXPECT_TRUE(from_another_site({.sec_fetch_site = "cross-site", .origin = "https://evil.example", .host = "bridge:8443", .tls = true}));
  // Another port or name of the same site is another origin, and may be another program.
  EXPECT_TRUE(from_another_site({.sec_fetch_site = "same-site", .origin = "https://bridge:9443", .host = "bridge:8443", .tls = true}));
}

TEST(RequestOrigin, WithoutFetchMetadataTheOriginMustBeThisServersOwn) {
  EXPECT_FALSE(from_another_site({.sec_fetch_site = "", .origin = "https://10.0.0.7:8443", .host = "10.0.0.7:8443", .tls = true}));
  EXPECT_FALSE(from_another_site({.sec_fetch_site = "", .origin = "http://127.0.0.1:8080", .host = "127.0.0.1:8080", .tls = false}));
  EXPECT_TRUE(from_another_site({.sec_fetch_site = "", .origin = "http://10.0.0.7:8443", .host = "10.0.0.7:8443", .tls = true}))
      << "the page over plain HTTP is another origin than the server over HTTPS";
  EXPECT_TRUE(from_another_site({.sec_fetch_site = "", .origin = "https://evil.example", .host = "10.0.0.7:8443", .tls = true}));
  EXPECT_TRUE(from_another_site({.sec_fetch_site = "", .origin = "null", .host = "10.0.0.7:8443", .tls = true}));
  EXPECT_TRUE(from_another_site({.sec_fetch_site = "", .origin = "https://10.0.0.7:8443", .host = "", .tls = true}));
}

}  // namespace
}  // namespace unima
