#include "monitor/monitor_sinks.hpp"

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <stdexcept>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "monitor/log_path.hpp"

namespace unima::monitor {

namespace {

// False on an error other than EINTR; errno tells which.
bool write_all(int fd, std::string_view bytes) {
  while (!bytes.empty()) {
    const auto n = ::write(fd, bytes.data(), bytes.size());
    if (n < 0) {
      if (errno == EINTR) continue;
      return false;
    }
    bytes.remove_prefix(static_cast<std::size_t>(n));
  }
  return true;
}

}  // namespace

RotatingFileSink::RotatingFileSink(std::string path, std::uint64_t max_size, unsigned max_files,
                                   FileAppender::Route route, std::string purpose, std::string_view key)
    : path_(std::move(path)), max_size_(max_size), max_files_(max_files), route_(route), purpose_(std::move(purpose)) {
  const auto directory = std::filesystem::path(path_).parent_path();
  std::error_code ignored;  // open() says what went wrong
  if (!directory.empty()) std::filesystem::create_directories(directory, ignored);
  if (open()) return;
  const int error = errno;
  if (const auto refused = error == ELOOP ? refused_log_path(path_) : std::nullopt)
    throw std::runtime_error(fmt::format("{}: {}", key, *refused));
  throw std::runtime_error(fmt::format("{}: cannot open {}: {}", key, path_, std::strerror(error)));
}

RotatingFileSink::~RotatingFileSink() { close(); }

bool RotatingFileSink::open() {
  auto file = std::make_unique<FileAppender>(path_, route_, max_size_, std::move(spare_stage_));
  if (!file->is_open()) return false;
  file_ = std::move(file);
  return true;
}

void RotatingFileSink::close() {
  if (!file_) return;
  if (!file_->flush()) write_failed();
  spare_stage_ = file_->release_stage();
  file_.reset();
}

void RotatingFileSink::rotate() {
  close();
  // The oldest goes first, so that no rename replaces a file: ext4 writes a file renamed
  // over another one out to disk at once (auto_da_alloc), on this thread, at every rotation.
  ::unlink((path_ + "." + std::to_string(max_files_)).c_str());
  for (unsigned i = max_files_; i > 1; --i)
    ::rename((path_ + "." + std::to_string(i - 1)).c_str(), (path_ + "." + std::to_string(i)).c_str());
  ::rename(path_.c_str(), (path_ + ".1").c_str());
  if (!open()) write_failed();  // the next append tries again
}

// On the writer thread, so the clock is read only while an outage lasts: a busy port's
// successful writes cost nothing more.
void RotatingFileSink::write_failed() {
  const int error = errno;
  if (outage_.failed(WriteOutage::Clock::now()))
    spdlog::error("{}: cannot write {}: {}; lines are lost until it works again (logged once, and when it has "
                  "worked again for {} s)", purpose_, path_, std::strerror(error),
                  std::chrono::duration_cast<std::chrono::seconds>(WriteOutage::default_settle).count());
}

void RotatingFileSink::write_succeeded() {
  if (!outage_.failing()) return;
  if (const auto recovery = outage_.succeeded(WriteOutage::Clock::now()))
    spdlog::info("{}: writing {} again; {} writes failed over {:.1f} s, their lines lost", purpose_, path_,
                 recovery->failed_writes, std::chrono::duration<double>(recovery->lasted).count());
}

void RotatingFileSink::append(std::string_view bytes) {
  if (bytes.empty()) return;
  if (!file_ && !open()) return write_failed();
  if (!file_->append(bytes)) return write_failed();
  write_succeeded();
}

void RotatingFileSink::flush() {
  if (file_ && !file_->flush()) write_failed();
}

void RotatingFileSink::write(std::string_view lines) {
  if (size() + lines.size() <= max_size_) return append(lines);  // most batches: no line is looked at
  // Lines go out in runs that fit the current file: one write per run, rotation between.
  std::size_t run_start = 0;
  std::uint64_t run_size = 0;
  std::size_t at = 0;
  while (at < lines.size()) {
    auto end = lines.find('\n', at);
    end = end == std::string_view::npos ? lines.size() : end + 1;
    const auto line_size = end - at;
    if (size() + run_size + line_size > max_size_ && size() + run_size > 0) {
      append(lines.substr(run_start, at - run_start));
      rotate();
      run_start = at;
      run_size = 0;
    }
    run_size += line_size;
    at = end;
  }
  append(lines.substr(run_start));
}

void StdoutSink::write(std::string_view lines) {
  if (write_all(STDOUT_FILENO, lines)) return;
  if (!failed_) spdlog::error("monitor: cannot write to standard output: {}", std::strerror(errno));
  failed_ = true;
}

}  // namespace unima::monitor
