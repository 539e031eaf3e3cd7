// web::BasicAuth (http.users, SPEC §13): the users file, the Authorization header, what is
// judged without a hash and what a hash then decides. Hashes made with `openssl passwd`.

#include <gtest/gtest.h>

#include "tests/support/base64.hpp"
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

std::string header(const std::string& credentials) { return "Basic " + test_support::base64(credentials); }

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

// What the loop does with the judgement and the worker with the check, in one.
BasicAuth::Judgement decide(BasicAuth& auth, const std::string& authorization) {
  auto judgement = auth.judge(authorization);
  if (judgement.verdict != BasicAuth::Verdict::check) return judgement;
  const auto& check = *judgement.check;
  if (!check.passed(hash_matches(check.password, check.hash))) return {BasicAuth::Verdict::refused, {}, {}};
  auth.remember(check);
  return {BasicAuth::Verdict::allowed, check.user, {}};
}

TEST(BasicAuth, TheRightPasswordPassesAndEveryOtherAnswerIsRefused) {
  auto auth = BasicAuth::parse(users_file, "users");
  EXPECT_EQ(auth.users(), 2u);
  const auto admin = decide(auth, header("admin:secret"));
  EXPECT_EQ(admin.verdict, BasicAuth::Verdict::allowed);
  EXPECT_EQ(admin.user, "admin");
  EXPECT_EQ(decide(auth, header("tech:tech pass")).verdict, BasicAuth::Verdict::allowed);
  EXPECT_EQ(decide(auth, "basic " + header("tech:tech pass").substr(6)).verdict, BasicAuth::Verdict::allowed);
  for (const auto& wrong : {header("admin:Secret"), header("admin:"), header("nobody:secret"), header("admin"),
                            std::string("Bearer abc"), std::string(""), std::string("Basic !!!!")})
    EXPECT_EQ(decide(auth, wrong).verdict, BasicAuth::Verdict::refused) << wrong;
}

TEST(BasicAuth, WhatNeedsNoHashIsJudgedAtOnceAndTheRestNamesTheHashToCompute) {
  auto auth = BasicAuth::parse(users_file, "users");
  // No name and password at all: refused without a hash.
  for (const auto& none : {std::string(""), std::string("Bearer abc"), std::string("Basic !!!!"), header("admin")})
    EXPECT_EQ(auth.judge(none).verdict, BasicAuth::Verdict::refused) << none;

  const auto first = auth.judge(header("admin:secret"));
  ASSERT_EQ(first.verdict, BasicAuth::Verdict::check);
  EXPECT_EQ(first.check->user, "admin");
  EXPECT_EQ(first.check->password, "secret");
  EXPECT_TRUE(first.check->known_user);
  EXPECT_EQ(first.check->authorization, header("admin:secret"));
  EXPECT_TRUE(first.check->passed(true));
  EXPECT_FALSE(first.check->passed(false));

  // An unknown name costs a hash like a known one, and never passes.
  const auto unknown = auth.judge(header("nobody:secret"));
  ASSERT_EQ(unknown.verdict, BasicAuth::Verdict::check);
  EXPECT_FALSE(unknown.check->known_user);
  EXPECT_FALSE(unknown.check->hash.empty());
  EXPECT_FALSE(unknown.check->passed(true));

  // Once it passed, the same header is allowed with no hash (a browser sends it each time).
  auth.remember(*first.check);
  const auto again = auth.judge(header("admin:secret"));
  EXPECT_EQ(again.verdict, BasicAuth::Verdict::allowed);
  EXPECT_EQ(again.user, "admin");
  EXPECT_FALSE(again.check);
  EXPECT_EQ(auth.judge(header("admin:secret2")).verdict, BasicAuth::Verdict::check);
}

TEST(BasicAuth, OnlyTheLatestHeadersThatPassedAreRemembered) {
  auto auth = BasicAuth::parse(users_file, "users");
  // remember() is given checks that passed; the hash is not its business.
  auto check_for = [&](int i) { return *auth.judge(header("admin:pass" + std::to_string(i))).check; };
  for (int i = 0; i <= static_cast<int>(BasicAuth::remembered); ++i) auth.remember(check_for(i));
  EXPECT_EQ(auth.judge(header("admin:pass0")).verdict, BasicAuth::Verdict::check) << "the oldest is forgotten";
  EXPECT_EQ(auth.judge(header("admin:pass1")).verdict, BasicAuth::Verdict::allowed);
  EXPECT_EQ(auth.judge(header("admin:pass" + std::to_string(BasicAuth::remembered))).verdict, BasicAuth::Verdict::allowed);
}

TEST(BasicAuth, HashesOfEveryKindCryptReadsAreCompared) {
  // openssl passwd -6 / -5 (above); bcrypt at the lowest cost, made by python3's crypt.
  EXPECT_TRUE(hash_matches("x", "$2b$04$ZZmNNmV3.Qv5gTBkvJ2Hq.vqwWloMx4rcqioFBd3amcsr50tKhI7m"));
  EXPECT_FALSE(hash_matches("y", "$2b$04$ZZmNNmV3.Qv5gTBkvJ2Hq.vqwWloMx4rcqioFBd3amcsr50tKhI7m"));
  EXPECT_FALSE(hash_matches("x", "$2b$04$broken"));
  std::string password = "secret";
  forget_password(password);
  EXPECT_TRUE(password.empty());
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
