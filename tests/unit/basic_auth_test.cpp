// web::BasicAuth (http.users, SPEC §13): the users file, the Authorization header, and the
// limit on checks that compute a hash. Hashes made with `openssl passwd`.

#include <gtest/gtest.h>

#include "web/basic_auth.hpp"

namespace unima::web {
namespace {

using namespace std::chrono_literals;

// openssl passwd -6 -salt salzsalz secret; openssl passwd -5 -salt pepper123 'tech pass'
const std::string users_file =
    "# who may open the page\n"
    "admin:$6$salzsalz$T6JPgc5oSlQmLkWq.mzSbtz8riZYp5RKogAdkAMphpHutqbzTWM.R2hHZXzRwqaHTGPbckcwMimHDhrrzvUs40\n"
    "\n"
    "tech:$5$pepper123$vgjWKLR/duoewu/bVpLI7OrXrMWgOifAUu7aCh/oDH3\r\n";

std::string header(const std::string& credentials) {
  static const char* alphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out = "Basic ";
  for (std::size_t i = 0; i < credentials.size(); i += 3) {
    const std::uint32_t n = static_cast<std::uint8_t>(credentials[i]) << 16 |
                            (i + 1 < credentials.size() ? static_cast<std::uint8_t>(credentials[i + 1]) << 8 : 0) |
                            (i + 2 < credentials.size() ? static_cast<std::uint8_t>(credentials[i + 2]) : 0);
    out += alphabet[n >> 18 & 63];
    out += alphabet[n >> 12 & 63];
    out += i + 1 < credentials.size() ? alphabet[n >> 6 & 63] : '=';
    out += i + 2 < credentials.size() ? alphabet[n & 63] : '=';
  }
  return out;
}

TEST(Base64, DecodesWithAndWithoutPaddingAndRefusesWhatIsNotBase64) {
  EXPECT_EQ(decode_base64("dXNlcjpwYXNz"), "user:pass");
  EXPECT_EQ(decode_base64("YWRtaW46c2VjcmV0"), "admin:secret");
  EXPECT_EQ(decode_base64("YQ=="), "a");
  EXPECT_EQ(decode_base64("YQ"), "a");
  EXPECT_EQ(decode_base64("YWI="), "ab");
  EXPECT_EQ(decode_base64(""), "");
  EXPECT_FALSE(decode_base64("YW*i"));
  EXPECT_FALSE(decode_base64("Y"));
  EXPECT_FALSE(decode_base64("YW Ji"));
}

TEST(BasicAuth, TheRightPasswordPassesAndEveryOtherAnswerIsRefused) {
  auto auth = BasicAuth::parse(users_file, "users");
  EXPECT_EQ(auth.users(), 2u);
  const auto now = BasicAuth::Clock::now();
  const auto admin = auth.check(header("admin:secret"), now);
  EXPECT_EQ(admin.verdict, BasicAuth::Verdict::allowed);
  EXPECT_EQ(admin.user, "admin");
  EXPECT_EQ(auth.check(header("tech:tech pass"), now).verdict, BasicAuth::Verdict::allowed);
  EXPECT_EQ(auth.check("basic " + header("tech:tech pass").substr(6), now).verdict, BasicAuth::Verdict::allowed);
  for (const auto& wrong : {header("admin:Secret"), header("admin:"), header("nobody:secret"), header("admin"),
                            std::string("Bearer abc"), std::string(""), std::string("Basic !!!!")})
    EXPECT_EQ(auth.check(wrong, now + 10s).verdict, BasicAuth::Verdict::refused) << wrong;
}

TEST(BasicAuth, CredentialsThatPassedPassAgainWithoutAHashAndGuessesAreLimited) {
  auto auth = BasicAuth::parse(users_file, "users");
  auto now = BasicAuth::Clock::now();
  ASSERT_EQ(auth.check(header("admin:secret"), now).verdict, BasicAuth::Verdict::allowed);
  // A browser sends the same header with every request: no limit for it.
  for (int i = 0; i < 100; ++i) ASSERT_EQ(auth.check(header("admin:secret"), now).verdict, BasicAuth::Verdict::allowed);
  // Guesses: a burst, then one each 1/checks_per_second.
  int refused = 0;
  int too_many = 0;
  for (unsigned i = 0; i < BasicAuth::check_burst + 5; ++i) {
    const auto verdict = auth.check(header("admin:guess" + std::to_string(i)), now).verdict;
    refused += verdict == BasicAuth::Verdict::refused;
    too_many += verdict == BasicAuth::Verdict::too_many;
  }
  EXPECT_EQ(refused, static_cast<int>(BasicAuth::check_burst) - 1);  // one token went to admin's first login
  EXPECT_EQ(too_many, 6);
  EXPECT_EQ(auth.check(header("tech:tech pass"), now).verdict, BasicAuth::Verdict::too_many);
  EXPECT_EQ(auth.check(header("admin:secret"), now).verdict, BasicAuth::Verdict::allowed) << "remembered";
  now += 1s;
  EXPECT_EQ(auth.check(header("tech:tech pass"), now).verdict, BasicAuth::Verdict::allowed);
}

TEST(BasicAuth, AFileItCannotUseIsRefusedNamingTheLine) {
  const auto error = [](const std::string& text) {
    try {
      (void)BasicAuth::parse(text, "http.users f");
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_EQ(error("# nobody\n"), "http.users f: lists no user");
  EXPECT_EQ(error("admin:$6$a$b\nbob\n"), "http.users f:2: expected name:password-hash");
  EXPECT_EQ(error(":$6$a$b\n"), "http.users f:1: expected name:password-hash");
  EXPECT_EQ(error("bob:secret\n"),
            "http.users f:1: 'bob' has no password hash crypt(3) reads ($6$, $5$, $2b$, $2y$ or $y$; make one with "
            "`openssl passwd -6`)");
  EXPECT_EQ(error("bob:$1$md5$xyz\n").substr(0, 35), "http.users f:1: 'bob' has no passwo");
  EXPECT_EQ(error("a:$6$x$y\na:$5$x$y\n"), "http.users f:2: 'a' is listed twice");
}

}  // namespace
}  // namespace unima::web
