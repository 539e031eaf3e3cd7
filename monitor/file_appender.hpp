#pragma once
// Appends to one file for the monitor's writer thread, bypassing the page cache where the
// file system allows it.
//
// Why: at full TCP load the monitor writes about 90 MB/s. Through the page cache the
// kernel copies every byte, allocates and accounts a page per 4 KiB, and frees it all
// again when rotation deletes the oldest file: most of the writer's CPU time, taken from
// the event loop and the clients on a small gateway. Written with O_DIRECT, whole blocks
// go from our buffer to the disk with none of that. O_DIRECT only takes whole aligned
// blocks, so the lines are staged in an aligned buffer; whole blocks go out when it is
// full or on flush(), and the last, partial block through the page cache on flush(). A
// block begun through the page cache is finished through it: direct writes only ever go
// past the end of the file, where no reader can hold a cached page.
// Readers (`tail -F`, `unima-bridge monitor --follow`) see the lines at the latest on the
// next flush(), when the stage fills, or `tail_delay` after they came, whichever is first.
//
// Where O_DIRECT is refused (tmpfs, some network file systems) or a write fails, the
// appender writes through the page cache instead, as any log file.

#include <chrono>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>

namespace unima::monitor {

class FileAppender {
 public:
  static constexpr std::size_t block = 4096;  // a multiple of every disk's logical block
  static constexpr std::size_t stage_capacity = 1 << 20;
  static constexpr std::chrono::milliseconds tail_delay{100};
  static constexpr std::uint64_t reserve_step = 4 << 20;

  enum class Route { direct_where_possible, page_cache };

  struct FreeAligned {
    void operator()(char* p) const;
  };
  /// The aligned buffer whole blocks are written from (stage_capacity bytes).
  using Stage = std::unique_ptr<char, FreeAligned>;

  /// Opens or creates `path` (0640) to append to; false from is_open() with errno set
  /// when it cannot (ELOOP: `path` is a symbolic link, never followed; monitor/log_path).
  /// With `reserve_up_to` > 0 the file's disk blocks are reserved ahead of the appends,
  /// never past that size (see reserve_for). `stage`, when given, is the released stage
  /// of an earlier file (see release_stage).
  explicit FileAppender(const std::string& path, Route route = Route::direct_where_possible,
                        std::uint64_t reserve_up_to = 0, Stage stage = {});
  /// Flushes, gives back whole blocks reserved past the end, then closes.
  ~FileAppender();
  FileAppender(const FileAppender&) = delete;
  FileAppender& operator=(const FileAppender&) = delete;

  bool is_open() const { return fd_ >= 0; }
  /// Whether whole blocks bypass the page cache (else everything goes through it).
  bool direct() const { return direct_fd_ >= 0; }
  /// The file's size once everything appended is written.
  std::uint64_t size() const { return base_ + staged_; }

  /// Appends whole lines (`bytes` ends with a newline, as the monitor's sinks write). False
  /// (errno set) when they could not be written: they are lost, and so is the beginning of
  /// a line whose rest was lost; the file is cut back to its last whole line, with no hole,
  /// and what is appended next follows that line.
  bool append(std::string_view bytes);
  /// Everything appended is in the file (readers see it) when this returns true.
  bool flush();
  /// After flush(), just before the appender is destroyed: its stage, for the next file.
  /// A stage freed and allocated again at every rotation costs a page fault for every
  /// 4 KiB of it (10 rotations a second at full load).
  Stage release_stage();

 private:
  void reserve_for(std::uint64_t end);
  bool write_whole_blocks();
  bool write_through_page_cache(std::uint64_t offset, std::string_view bytes);
  void note_written(const char* bytes, std::size_t size, std::uint64_t offset);
  bool lose_unwritten();
  void leave_direct_route(std::uint64_t end);
  bool fall_back_to_page_cache();

  int fd_ = -1;
  int direct_fd_ = -1;
  Stage stage_;
  std::uint64_t base_ = 0;     // the file offset of stage_[0]: a block boundary when direct
  std::size_t staged_ = 0;     // bytes in the stage; without O_DIRECT always 0
  std::size_t visible_ = 0;    // of those, already in the file through the page cache
  std::chrono::steady_clock::time_point hidden_since_{};  // when the first unwritten byte came
  std::uint64_t reserve_up_to_;
  std::uint64_t reserved_ = 0;  // the file's blocks are allocated up to here
  std::uint64_t line_end_ = 0;  // the file offset after the last newline written
};

}  // namespace unima::monitor
