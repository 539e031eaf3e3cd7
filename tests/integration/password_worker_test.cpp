// io::PasswordWorker in this process, over a real io_context (issue 43, finding 7): a check
// abandoned because its client went never answers, though the checks handed over before
// and after it do; and its ticket may be abandoned after the worker is gone.

#include <gtest/gtest.h>

#include <chrono>
#include <memory>
#include <optional>
#include <vector>

#include "io/http/password_worker.hpp"

namespace unima::io {
namespace {

// bcrypt of "right", cost 12 (python3's crypt, as tests/integration/login_test makes them).
constexpr auto hash = "$2b$12$Dl/Xs6WZuTjZXq4LuMraLOs9R7xuAq3E/emd2GC7PlS6U0bJ9kODS";

TEST(PasswordWorker, AnAbandonedCheckNeverAnswersAndTheOthersDo) {
  asio::io_context io;
  PasswordWorker worker(io);
  std::vector<std::optional<bool>> answers(3);
  std::vector<PasswordWorker::Ticket> tickets;
  for (std::size_t i = 0; i < answers.size(); ++i)
    tickets.push_back(worker.check(i == 2 ? "right" : "wrong", hash, [&answers, i](bool matched) { answers[i] = matched; }));
  tickets[1].abandon();
  const auto waiting = asio::make_work_guard(io);  // the answers are posted from the worker's thread
  // The worker takes them in order: once the last has answered, the abandoned one would have.
  for (int turns = 0; turns < 600 && !answers[2]; ++turns) io.run_one_for(std::chrono::milliseconds(100));
  ASSERT_TRUE(answers[2].has_value()) << "no answer within a minute";
  io.poll();
  EXPECT_EQ(answers[0], std::optional(false));
  EXPECT_EQ(answers[1], std::nullopt) << "the abandoned check answered";
  EXPECT_EQ(answers[2], std::optional(true));
  EXPECT_EQ(worker.pending(), 0u);
}

TEST(PasswordWorker, ATicketOutlivesItsWorker) {
  asio::io_context io;
  PasswordWorker::Ticket ticket;
  bool answered = false;
  {
    PasswordWorker worker(io);
    ticket = worker.check("right", hash, [&answered](bool) { answered = true; });
  }
  ticket.abandon();
  io.poll();
  EXPECT_FALSE(answered);
}

}  // namespace
}  // namespace unima::io
