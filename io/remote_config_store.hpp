#pragma once
// Where the configs sent from afar live (SPEC §19, "Where it lives"): the operator's file
// is never written; each applied remote config is kept, numbered, in a directory of the
// state directory, with its source, time, author and the sha256 of the operator's file it
// replaced, and one record says which of them is in force (or that the file is). The last
// `keep` stay. What runs at start and on SIGHUP is chosen from this by
// app/config_in_force.
//
// The directory, made 0700 when the first config is kept (never at start):
//   000001.yaml   the text exactly as it was sent, 0600 (configs hold passwords)
//   000001.json   its record: {"number":1,"id":…,"source":…,"by":…,"applied_at":…,
//                              "replaced_file":…,"replaced_sha256":…,"replaced_number":…}
//                 replaced_number: the remote config it replaced, null for the operator's
//                 file (a record written before it was kept has none: not known)
//   in-force.json {"number": 1 | null, "last_number": N}: the config in force (null: the
//                 operator's file) and the highest number ever given, so none is reused
// Each is written by atomic replace (io/durable_file). A record that cannot be read is
// skipped with a warning; an in-force record naming an entry that is not there (or cannot
// be read) means the operator's file is in force. Each call blocks on the disk: the
// daemon makes them at start, on SIGHUP, and once per remote change.

#include <chrono>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "config/config.hpp"
#include "remote/change_answer.hpp"

namespace unima::io {

struct StoredConfig {
  unsigned number = 0;             // 1, 2, 3 … never reused
  std::string id;                  // remote::change_id(text): sha256, lower-case hex
  remote::Source source = remote::Source::cli;
  std::string by;                  // author
  std::string applied_at;          // UTC, "2026-11-29T22:30:05.000000Z" (platform/utc_time)
  std::string replaced_file;       // the operator's file (path)
  std::string replaced_sha256;     // its sha256 when this was applied
  std::optional<unsigned> replaced_number;  // the remote config this replaced; none: the operator's file
  bool replaced_known = true;      // false: an older record, which does not say what it replaced
  std::filesystem::path text_path; // where the text is kept
  bool operator==(const StoredConfig&) const = default;
};

class RemoteConfigStore {
 public:
  /// SPEC §19's default of remote_config.keep.
  static constexpr unsigned default_keep = 10;

  /// Looks at nothing yet: the directory is read by each call, and made by the first keep().
  RemoteConfigStore(std::filesystem::path directory, unsigned keep);
  /// `remote-config` in the directory of the operator's config's state file; empty when
  /// `state.file: none` (then nothing can be kept and remote changes are refused).
  static std::filesystem::path directory_for(const config::Config& operator_config);
  const std::filesystem::path& directory() const { return directory_; }
  /// Keeps `text` as the next number and puts it in force, durably (file fsync'ed, atomic
  /// rename, directory fsync'ed) before it returns; forgets the oldest beyond `keep`,
  /// never the one in force. Throws std::system_error / std::runtime_error naming the path.
  /// `replaced_number`: the remote config in force until now; none when the operator's file was.
  StoredConfig keep(std::string_view text, remote::Source source, std::string by, std::string replaced_file,
                    std::string replaced_sha256, std::optional<unsigned> replaced_number,
                    std::chrono::system_clock::time_point when);
  /// The operator's file is in force again (a revert, or the file changed). Nothing to do,
  /// and nothing made, when no config was ever kept.
  void put_file_in_force();
  std::optional<StoredConfig> in_force() const;
  std::vector<StoredConfig> history() const;  // newest first
  /// The entry `number`, while it is kept and readable.
  std::optional<StoredConfig> entry(unsigned number) const { return read_entry(number); }
  /// The text as it was sent. Throws std::runtime_error naming the path when it is gone.
  std::string text(const StoredConfig& stored) const;
  /// Takes effect at the next keep(), which forgets what is beyond it then.
  void set_keep(unsigned keep);

 private:
  struct InForceRecord {
    std::optional<unsigned> number;
    unsigned last_number = 0;
  };
  InForceRecord read_in_force() const;
  void write_in_force(const InForceRecord& record) const;
  std::optional<StoredConfig> read_entry(unsigned number) const;
  std::filesystem::path text_path(unsigned number) const;
  std::filesystem::path record_path(unsigned number) const;
  std::filesystem::path in_force_path() const;
  void make_directory() const;
  void forget_beyond_keep(std::optional<unsigned> in_force) const;

  std::filesystem::path directory_;
  unsigned keep_;
};

}  // namespace unima::io
