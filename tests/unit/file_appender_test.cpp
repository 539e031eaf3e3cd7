// The monitor's file appender (monitor/file_appender.hpp): whatever way the bytes take —
// whole blocks past the page cache, the partial last block through it, or everything
// through it where O_DIRECT is refused or a direct write failed — the file holds exactly
// what was appended (less what a failed write lost — whole lines —, with no hole), in
// order, and readers see it after flush().

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/resource.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <cerrno>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "monitor/file_appender.hpp"
#include "tests/support/temp_files.hpp"

namespace unima::monitor {
namespace {

using test_support::read_file;
using test_support::TempDir;

// Lines of varying length, so that block and stage boundaries fall inside lines.
std::string lines(int first, int count) {
  std::string text;
  for (int n = first; n < first + count; ++n) text += "line " + std::to_string(n) + std::string(n % 97, '.') + "\n";
  return text;
}

bool file_system_takes_direct_writes(const std::filesystem::path& dir) {
  const auto probe = (dir / "probe").string();
  const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_DIRECT, 0600);
  if (fd >= 0) ::close(fd);
  std::filesystem::remove(probe);
  return fd >= 0;
}

TEST(FileAppender, HoldsExactlyWhatWasAppendedAcrossBlocksAndStages) {
  TempDir dir;
  const auto path = dir.path() / "monitor.log";
  std::string expected;
  {
    FileAppender file(path.string());
    ASSERT_TRUE(file.is_open());
    // 2.5 stages in pieces of every size; flushes at odd moments in between.
    for (int n = 0; expected.size() < 5 * FileAppender::stage_capacity / 2; n += 50) {
      const auto piece = lines(n, 50);
      ASSERT_TRUE(file.append(piece));
      expected += piece;
      EXPECT_EQ(file.size(), expected.size());
      if (n % 1000 == 0) {
        ASSERT_TRUE(file.flush());
        EXPECT_EQ(read_file(path), expected);
      }
    }
    ASSERT_TRUE(file.flush());
    EXPECT_EQ(read_file(path), expected) << "all of it visible after flush()";
    ASSERT_TRUE(file.append("one more\n"));
    expected += "one more\n";
  }
  EXPECT_EQ(read_file(path), expected) << "the rest written when it closes";
}

TEST(FileAppender, GoesOnFromTheMiddleOfABlockOfAnExistingFile) {
  TempDir dir;
  const auto path = dir.path() / "monitor.log";
  const auto before = lines(0, 60);  // not a multiple of a block
  ASSERT_NE(before.size() % FileAppender::block, 0u);
  std::ofstream(path, std::ios::binary) << before;
  {
    FileAppender file(path.string());
    EXPECT_EQ(file.size(), before.size());
    if (file_system_takes_direct_writes(dir.path())) {
      EXPECT_TRUE(file.direct()) << "the last block read back into the stage, whole blocks still direct";
    }
    ASSERT_TRUE(file.append(lines(60, 3000)));
  }
  EXPECT_EQ(read_file(path), before + lines(60, 3000));
}

// Which pages of `path` are in the page cache (mincore of a mapping that is never touched).
std::vector<bool> cached_pages(const std::filesystem::path& path) {
  const int fd = ::open(path.c_str(), O_RDONLY);
  const auto size = std::filesystem::file_size(path);
  void* map = ::mmap(nullptr, size, PROT_READ, MAP_SHARED, fd, 0);
  ::close(fd);
  const auto page = static_cast<std::size_t>(::sysconf(_SC_PAGESIZE));
  std::vector<unsigned char> residency((size + page - 1) / page);
  EXPECT_EQ(::mincore(map, size, residency.data()), 0);
  ::munmap(map, size);
  std::vector<bool> cached;
  for (const auto r : residency) cached.push_back((r & 1) != 0);
  return cached;
}

// A reader holding a cached page while a direct write replaces its block would keep it,
// stale: so the block the last flush() began through the page cache is finished through
// it, and direct writes go only past the end of the file.
TEST(FileAppender, ABlockBegunThroughThePageCacheIsFinishedThroughIt) {
  TempDir dir;
  if (!file_system_takes_direct_writes(dir.path())) GTEST_SKIP() << dir.path() << " refuses O_DIRECT";
  const auto path = dir.path() / "monitor.log";
  const std::string block_of_text(FileAppender::block, 'x');
  {
    FileAppender file(path.string());
    ASSERT_TRUE(file.append("the first line\n"));
    ASSERT_TRUE(file.flush());  // block 0 begun through the page cache
    for (int n = 0; n < 3; ++n) ASSERT_TRUE(file.append(block_of_text));
    ASSERT_TRUE(file.flush());
    const auto cached = cached_pages(path);
    ASSERT_GE(cached.size(), 3u);
    EXPECT_TRUE(cached[0]) << "block 0 finished through the page cache, not replaced under a reader";
    EXPECT_FALSE(cached[1]) << "block 1 written past the page cache";
    EXPECT_FALSE(cached[2]);
  }
  EXPECT_EQ(read_file(path), "the first line\n" + block_of_text + block_of_text + block_of_text);
}

TEST(FileAppender, BypassesThePageCacheWhereTheFileSystemAllowsIt) {
  TempDir dir;
  if (!file_system_takes_direct_writes(dir.path())) GTEST_SKIP() << dir.path() << " refuses O_DIRECT";
  FileAppender file((dir.path() / "monitor.log").string());
  EXPECT_TRUE(file.direct());
}

// Rotation hands the closed file's stage to the next file (no page faults to map a fresh
// one): both files hold exactly their bytes, and the next file really writes from it.
TEST(FileAppender, AStageReleasedByOneFileServesTheNext) {
  TempDir dir;
  if (!file_system_takes_direct_writes(dir.path())) GTEST_SKIP() << dir.path() << " refuses O_DIRECT";
  const auto first_path = dir.path() / "monitor.log.1";
  const auto next_path = dir.path() / "monitor.log";
  const auto first_text = lines(0, 20000);  // more than a stage: whole blocks went out direct
  const auto next_text = lines(20000, 3000);
  ASSERT_GT(first_text.size(), FileAppender::stage_capacity);
  FileAppender::Stage stage;
  {
    FileAppender first(first_path.string());
    ASSERT_TRUE(first.append(first_text));
    ASSERT_TRUE(first.flush());
    stage = first.release_stage();
    EXPECT_EQ(first.size(), first_text.size());
  }
  ASSERT_TRUE(stage);
  const char* const reused = stage.get();
  {
    FileAppender next(next_path.string(), FileAppender::Route::direct_where_possible, 0, std::move(stage));
    EXPECT_TRUE(next.direct());
    ASSERT_TRUE(next.append(next_text));
    ASSERT_TRUE(next.flush());
    EXPECT_EQ(next.release_stage().get(), reused);
  }
  EXPECT_EQ(read_file(first_path), first_text);
  EXPECT_EQ(read_file(next_path), next_text);
}

// Sets the largest file this process may write (RLIMIT_FSIZE) for a scope: past it, writes
// fail with EFBIG — the direct ones as well, which is how a direct write is made to fail
// here (a full disk would do the same, and no test can fill one).
class FileSizeLimit {
 public:
  explicit FileSizeLimit(rlim_t bytes) {
    ::getrlimit(RLIMIT_FSIZE, &saved_);
    old_handler_ = std::signal(SIGXFSZ, SIG_IGN);  // else the kernel's signal ends the test
    rlimit limit = saved_;
    limit.rlim_cur = bytes;
    ::setrlimit(RLIMIT_FSIZE, &limit);
  }
  ~FileSizeLimit() {
    ::setrlimit(RLIMIT_FSIZE, &saved_);
    std::signal(SIGXFSZ, old_handler_);
  }
  FileSizeLimit(const FileSizeLimit&) = delete;
  FileSizeLimit& operator=(const FileSizeLimit&) = delete;

 private:
  rlimit saved_{};
  void (*old_handler_)(int) = nullptr;
};

// A direct write that fails says so (errno) and loses what it held, and the appender goes
// on through the page cache: what is appended once writing works again follows the last
// bytes written, with no hole where the lost ones would have been.
TEST(FileAppender, AfterAFailedDirectWriteItGoesOnThroughThePageCache) {
  TempDir dir;
  if (!file_system_takes_direct_writes(dir.path())) GTEST_SKIP() << dir.path() << " refuses O_DIRECT";
  const auto path = dir.path() / "monitor.log";
  const auto written_before = std::string(2 * FileAppender::block - 1, 'a') + "\n";  // whole blocks: direct
  const auto lost = lines(0, 30000);                                                  // more than a stage
  const auto written_after = lines(30000, 100);
  ASSERT_GT(lost.size(), FileAppender::stage_capacity);
  {
    FileAppender file(path.string());
    ASSERT_TRUE(file.direct());
    ASSERT_TRUE(file.append(written_before));
    ASSERT_TRUE(file.flush());
    {
      const FileSizeLimit limit(written_before.size());
      errno = 0;
      EXPECT_FALSE(file.append(lost));
      EXPECT_EQ(errno, EFBIG);
    }
    EXPECT_FALSE(file.direct()) << "still writing past the page cache after a failed direct write";
    ASSERT_TRUE(file.append(written_after));
    EXPECT_EQ(read_file(path), written_before + written_after) << "appended at once through the page cache";
  }
  EXPECT_EQ(read_file(path), written_before + written_after);
}

// A write the limit cuts short puts part of its bytes in the file before it fails: they are
// cut off again, so that nothing of the lost lines is left behind the next ones — through
// the page cache, and through a direct write whose page-cache fallback fails too.
TEST(FileAppender, AWriteThatFailsPartWayLeavesNothingOfItBehind) {
  TempDir dir;
  for (const auto route : {FileAppender::Route::page_cache, FileAppender::Route::direct_where_possible}) {
    const auto path = dir.path() / (route == FileAppender::Route::page_cache ? "cached.log" : "direct.log");
    const auto written_before = std::string(2 * FileAppender::block - 1, 'a') + "\n";
    const auto lost = lines(0, 30000);  // more than a stage
    const auto written_after = lines(30000, 10);  // far shorter than what the limit let through
    FileAppender file(path.string(), route);
    ASSERT_TRUE(file.append(written_before));
    ASSERT_TRUE(file.flush());
    {
      const FileSizeLimit limit(written_before.size() + 5000);  // part of `lost` fits
      EXPECT_FALSE(file.append(lost));
    }
    EXPECT_EQ(file.size(), written_before.size());
    ASSERT_TRUE(file.append(written_after));
    ASSERT_TRUE(file.flush());
    EXPECT_EQ(read_file(path), written_before + written_after) << path;
  }
}

// A direct write ends at a block boundary, inside a line. When what follows it cannot be
// written, the beginning of that line is cut off too: the file ends with its last whole line,
// and the next lines follow it, never a piece of a lost line running into them.
TEST(FileAppender, AFailedWriteLeavesTheFileEndingWithItsLastWholeLine) {
  TempDir dir;
  if (!file_system_takes_direct_writes(dir.path())) GTEST_SKIP() << dir.path() << " refuses O_DIRECT";
  const auto path = dir.path() / "monitor.log";
  const auto text = lines(0, 300);
  const auto whole_blocks = text.size() / FileAppender::block * FileAppender::block;
  ASSERT_GE(whole_blocks, 2 * FileAppender::block);
  ASSERT_NE(text[whole_blocks - 1], '\n') << "the test needs a block boundary inside a line";
  const auto kept = text.substr(0, text.rfind('\n', whole_blocks - 1) + 1);
  const auto written_after = lines(300, 10);
  FileAppender file(path.string());
  ASSERT_TRUE(file.direct());
  ASSERT_TRUE(file.append(text));  // held in the stage
  {
    const FileSizeLimit limit(whole_blocks);  // the whole blocks go out direct, the rest fails
    errno = 0;
    EXPECT_FALSE(file.flush());
    EXPECT_EQ(errno, EFBIG);
  }
  EXPECT_EQ(read_file(path), kept);
  EXPECT_EQ(file.size(), kept.size());
  ASSERT_TRUE(file.append(written_after));
  ASSERT_TRUE(file.flush());
  EXPECT_EQ(read_file(path), kept + written_after);
}

// The route taken where O_DIRECT is refused (or a direct write failed): every append is
// in the file at once.
TEST(FileAppender, ThroughThePageCacheEveryAppendIsInTheFileAtOnce) {
  TempDir dir;
  const auto path = dir.path() / "monitor.log";
  {
    FileAppender file(path.string(), FileAppender::Route::page_cache);
    ASSERT_TRUE(file.is_open());
    EXPECT_FALSE(file.direct());
    ASSERT_TRUE(file.append(lines(0, 10)));
    EXPECT_EQ(read_file(path), lines(0, 10));
    ASSERT_TRUE(file.append(lines(10, 3000)));
    EXPECT_EQ(file.size(), lines(0, 3010).size());
    EXPECT_EQ(read_file(path), lines(0, 3010));
  }
  EXPECT_EQ(read_file(path), lines(0, 3010));
}

TEST(FileAppender, AFileThatCannotBeOpenedSaysWhy) {
  TempDir dir;
  FileAppender file((dir.path() / "missing" / "monitor.log").string());
  EXPECT_FALSE(file.is_open());
  EXPECT_EQ(errno, ENOENT);
}

}  // namespace
}  // namespace unima::monitor
