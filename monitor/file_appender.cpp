#include "monitor/file_appender.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>

namespace unima::monitor {

namespace {

// False on an error other than EINTR (errno tells which), or when the file system wrote
// nothing (a full disk may do that without an error: ENOSPC is then the honest errno).
bool pwrite_all(int fd, const char* data, std::size_t size, std::uint64_t offset) {
  while (size > 0) {
    const auto n = ::pwrite(fd, data, size, static_cast<off_t>(offset));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      if (n == 0) errno = ENOSPC;
      return false;
    }
    data += n;
    size -= static_cast<std::size_t>(n);
    offset += static_cast<std::uint64_t>(n);
  }
  return true;
}

}  // namespace

void FileAppender::FreeAligned::operator()(char* p) const { std::free(p); }

FileAppender::FileAppender(const std::string& path, Route route, std::uint64_t reserve_up_to, Stage stage)
    : stage_(std::move(stage)), reserve_up_to_(reserve_up_to) {
  // Read too: continuing an existing file in the middle of a block (a restart, a reload)
  // reads that block back into the stage, or every block of that file would go through
  // the page cache. A file we may only write is still appended to, that way.
  // O_NOFOLLOW: a symbolic link put in the file's place fails with ELOOP rather than have
  // the daemon append to (and rotate, and cut back) whatever it points at (SPEC §10).
  fd_ = ::open(path.c_str(), O_RDWR | O_CREAT | O_NOFOLLOW | O_CLOEXEC, 0640);
  if (fd_ < 0 && errno == EACCES) fd_ = ::open(path.c_str(), O_WRONLY | O_CREAT | O_NOFOLLOW | O_CLOEXEC, 0640);
  if (fd_ < 0) return;
  struct stat st{};
  if (::fstat(fd_, &st) != 0) {
    const int error = errno;
    ::close(fd_);
    fd_ = -1;
    errno = error;
    return;
  }
  const auto size = static_cast<std::uint64_t>(st.st_size);
  base_ = reserved_ = line_end_ = size;
  if (route == Route::page_cache) return;
  direct_fd_ = ::open(path.c_str(), O_WRONLY | O_DIRECT | O_NOFOLLOW | O_CLOEXEC);
  if (direct_fd_ < 0) return;  // not on this file system: through the page cache
  // The path is opened twice: both must be the file fstat'ed above, not one swapped in
  // between the two opens.
  struct stat direct_st{};
  if (::fstat(direct_fd_, &direct_st) != 0 || direct_st.st_dev != st.st_dev || direct_st.st_ino != st.st_ino) {
    ::close(direct_fd_);
    direct_fd_ = -1;
    return;
  }
  // Allocated here, touched only as lines come: an idle monitor costs no memory for it.
  if (!stage_) stage_.reset(static_cast<char*>(std::aligned_alloc(block, stage_capacity)));
  // The stage starts at the block the file ends in; its first bytes are already there.
  const std::size_t in_last_block = size % block;
  if (!stage_ || (in_last_block > 0 && ::pread(fd_, stage_.get(), in_last_block,
                                                static_cast<off_t>(size - in_last_block)) !=
                                           static_cast<ssize_t>(in_last_block))) {
    ::close(direct_fd_);
    direct_fd_ = -1;
    stage_.reset();
    return;
  }
  base_ = size - in_last_block;
  staged_ = visible_ = in_last_block;
}

FileAppender::Stage FileAppender::release_stage() {
  // A flush() that failed has cut its lines off already; appending from here on goes
  // through the page cache.
  if (staged_ > visible_) (void)flush();
  leave_direct_route(base_ + staged_);
  return std::move(stage_);
}

// From here on everything goes through the page cache, the file continuing at `end`.
void FileAppender::leave_direct_route(std::uint64_t end) {
  if (direct_fd_ >= 0) ::close(direct_fd_);
  direct_fd_ = -1;
  base_ = end;
  staged_ = visible_ = 0;
}

FileAppender::~FileAppender() {
  if (fd_ < 0) return;
  (void)flush();
  // Truncating to the size it has frees whole blocks reserved past the end. Only then:
  // ext4 writes a truncated file out when it is closed, a stall of milliseconds at every
  // rotation for a reservation of less than a block.
  struct stat st{};
  if (reserved_ / block > (size() + block - 1) / block && ::fstat(fd_, &st) == 0) (void)::ftruncate(fd_, st.st_size);
  if (direct_fd_ >= 0) ::close(direct_fd_);
  ::close(fd_);
}

// Appending into blocks the file already owns costs the kernel less than appending past
// them (ext4 reserves and accounts new blocks as they come), and a busy port appends tens
// of MB/s. KEEP_SIZE leaves the size, and so what readers and `tail -F` see, untouched.
// Reserved a step ahead, so a stopped daemon leaves at most one step unused on disk.
void FileAppender::reserve_for(std::uint64_t end) {
  if (end <= reserved_ || reserve_up_to_ == 0) return;
  const auto target = std::max(end, std::min(reserved_ + reserve_step, reserve_up_to_));
  if (::fallocate(fd_, FALLOC_FL_KEEP_SIZE, static_cast<off_t>(reserved_), static_cast<off_t>(target - reserved_)) == 0)
    reserved_ = target;
  else
    reserve_up_to_ = 0;  // not supported by this file system, or the disk is full: the write will say so
}

bool FileAppender::append(std::string_view bytes) {
  reserve_for(size() + bytes.size());
  if (direct_fd_ < 0) {
    if (!write_through_page_cache(base_, bytes)) return lose_unwritten();
    base_ += bytes.size();
    return true;
  }
  const auto now = std::chrono::steady_clock::now();
  while (!bytes.empty()) {
    if (staged_ == visible_) hidden_since_ = now;
    const auto n = std::min(bytes.size(), stage_capacity - staged_);
    std::memcpy(stage_.get() + staged_, bytes.data(), n);
    staged_ += n;
    bytes.remove_prefix(n);
    if (staged_ == stage_capacity) {
      if (!write_whole_blocks()) return false;
      if (direct_fd_ < 0) return append(bytes);  // fell back: the rest goes the same way
    }
  }
  if (staged_ > visible_ && now - hidden_since_ >= tail_delay) return flush();
  return true;
}

bool FileAppender::flush() {
  if (direct_fd_ < 0) return true;  // nothing is ever held back
  if (!write_whole_blocks()) return false;
  if (staged_ == visible_) return true;
  if (!write_through_page_cache(base_ + visible_, {stage_.get() + visible_, staged_ - visible_}))
    return lose_unwritten();
  visible_ = staged_;
  return true;
}

bool FileAppender::write_whole_blocks() {
  const auto whole = staged_ / block * block;
  if (whole == 0) return true;
  std::size_t direct_from = 0;
  if (visible_ > 0) {
    // The first block is partly in the file through the page cache already: the rest of
    // it goes the same way. A direct write over a cached page makes the kernel drop that
    // page, and a reader that holds it at that moment (`tail -F` reads exactly there)
    // would keep it, stale, with zeros where the new lines are.
    if (!write_through_page_cache(base_ + visible_, {stage_.get() + visible_, block - visible_}))
      return lose_unwritten();
    direct_from = block;
  }
  if (whole > direct_from) {
    if (!pwrite_all(direct_fd_, stage_.get() + direct_from, whole - direct_from, base_ + direct_from)) {
      visible_ = direct_from;  // the first block is in the file either way
      return fall_back_to_page_cache();
    }
    note_written(stage_.get() + direct_from, whole - direct_from, base_ + direct_from);
  }
  std::memmove(stage_.get(), stage_.get() + whole, staged_ - whole);
  base_ += whole;
  staged_ -= whole;
  visible_ = 0;
  return true;
}

bool FileAppender::write_through_page_cache(std::uint64_t offset, std::string_view bytes) {
  if (!pwrite_all(fd_, bytes.data(), bytes.size(), offset)) return false;
  note_written(bytes.data(), bytes.size(), offset);
  return true;
}

void FileAppender::note_written(const char* bytes, std::size_t size, std::uint64_t offset) {
  // From the end: a line is short, so this looks at one line, not at the whole write.
  if (const auto* newline = static_cast<const char*>(::memrchr(bytes, '\n', size)))
    line_end_ = offset + static_cast<std::uint64_t>(newline - bytes) + 1;
}

// What could not be written is lost, and so is what went before it of the same line: a
// direct write ends at a block boundary, inside a line, and a write that fails part-way (a
// full disk) may have put some of its bytes in the file. Left there, that piece of a line
// would run into the next line written. So the file is cut back to its last whole line, and
// the next lines follow that; through the page cache from here on, as after any failure,
// since the stage's blocks no longer match the file's.
bool FileAppender::lose_unwritten() {
  const int error = errno;
  if (::ftruncate(fd_, static_cast<off_t>(line_end_)) == 0) reserved_ = std::min(reserved_, line_end_);
  leave_direct_route(line_end_);
  stage_.reset();
  errno = error;
  return false;
}

// A direct write failed (the file system refused the alignment, the disk is full, ...):
// what is staged goes through the page cache, and so does everything after it.
bool FileAppender::fall_back_to_page_cache() {
  if (!write_through_page_cache(base_ + visible_, {stage_.get() + visible_, staged_ - visible_}))
    return lose_unwritten();
  leave_direct_route(base_ + staged_);
  stage_.reset();
  return true;
}

}  // namespace unima::monitor
