#include "io/remote_config_store.hpp"

#include <sys/stat.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <ctime>
#include <set>
#include <stdexcept>
#include <system_error>

#include <fmt/format.h>

#include "platform/utc_time.hpp"
#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>

#include "io/durable_file.hpp"

namespace unima::io {
namespace {

using nlohmann::json;

constexpr const char* in_force_name = "in-force.json";

std::string numbered(unsigned number, std::string_view extension) {
  return fmt::format("{:06}{}", number, extension);
}

// "000012.yaml" -> 12; anything else (in-force.json, a temporary, a stranger's file) -> nullopt.
std::optional<unsigned> number_of(const std::filesystem::path& name) {
  const auto extension = name.extension();
  if (extension != ".yaml" && extension != ".json") return std::nullopt;
  const auto stem = name.stem().string();
  if (stem.empty() || !std::all_of(stem.begin(), stem.end(), [](char c) { return c >= '0' && c <= '9'; }))
    return std::nullopt;
  unsigned number = 0;
  const auto [end, error] = std::from_chars(stem.data(), stem.data() + stem.size(), number);
  if (error != std::errc() || end != stem.data() + stem.size() || number == 0) return std::nullopt;
  return number;
}

// The numbers the directory holds a text or a record of, highest first. None when there is
// no directory.
std::vector<unsigned> numbers_in(const std::filesystem::path& directory) {
  std::set<unsigned, std::greater<>> numbers;
  std::error_code error;
  for (std::filesystem::directory_iterator it(directory, error), end; !error && it != end; it.increment(error))
    if (const auto number = number_of(it->path().filename())) numbers.insert(*number);
  return {numbers.begin(), numbers.end()};
}

std::optional<remote::Source> source_named(std::string_view name) {
  for (const auto source : {remote::Source::mqtt, remote::Source::http, remote::Source::cli})
    if (remote::source_name(source) == name) return source;
  return std::nullopt;
}

// The failure of a write, naming the file: durable_file's messages name the step
// ("write", "fdatasync") and the temporary at most.
[[noreturn]] void rethrow_naming(const std::filesystem::path& path, const std::system_error& e) {
  std::string what = e.what();
  if (const auto suffix = ": " + e.code().message(); what.ends_with(suffix)) what.resize(what.size() - suffix.size());
  throw std::system_error(e.code(), fmt::format("remote config store: {}: {}", path.string(), what));
}

void replace_owner_only(const std::filesystem::path& path, std::string_view content) {
  try {
    replace_file(path, content, FileAccess::owner_only);
  } catch (const std::system_error& e) {
    rethrow_naming(path, e);
  }
}

// A record's text field; a record without it is not one of ours.
std::string text_field(const json& record, const char* key) {
  const auto& value = record.at(key);
  if (!value.is_string()) throw std::runtime_error(fmt::format("'{}' is not a string", key));
  return value.get<std::string>();
}

}  // namespace

RemoteConfigStore::RemoteConfigStore(std::filesystem::path directory, unsigned keep)
    : directory_(std::move(directory)), keep_(keep) {}

std::filesystem::path RemoteConfigStore::directory_for(const config::Config& operator_config) {
  if (operator_config.state.file.empty()) return {};
  return std::filesystem::path(operator_config.state.file).parent_path() / "remote-config";
}

std::filesystem::path RemoteConfigStore::text_path(unsigned number) const { return directory_ / numbered(number, ".yaml"); }
std::filesystem::path RemoteConfigStore::record_path(unsigned number) const { return directory_ / numbered(number, ".json"); }
std::filesystem::path RemoteConfigStore::in_force_path() const { return directory_ / in_force_name; }

// 0700: the texts are 0600 already, but their names, authors and times are nobody else's
// business either. Only the last part is made so; what leads to it is the state
// directory's, made as the state file's would be.
void RemoteConfigStore::make_directory() const {
  std::error_code error;
  if (std::filesystem::is_directory(directory_, error)) return;
  if (const auto parent = directory_.parent_path(); !parent.empty()) {
    std::filesystem::create_directories(parent, error);
    if (error) throw std::system_error(error, fmt::format("remote config store: create the directory {}", parent.string()));
  }
  if (::mkdir(directory_.c_str(), 0700) != 0 && errno != EEXIST)
    throw std::system_error(errno, std::generic_category(),
                            fmt::format("remote config store: create the directory {}", directory_.string()));
  try {
    sync_directory(directory_);
  } catch (const std::system_error& e) {
    rethrow_naming(directory_, e);
  }
}

RemoteConfigStore::InForceRecord RemoteConfigStore::read_in_force() const {
  const auto path = in_force_path();
  try {
    const auto bytes = read_if_present(path);
    if (!bytes) return {};
    const auto record = json::parse(*bytes);
    InForceRecord read;
    if (const auto& number = record.at("number"); !number.is_null()) read.number = number.get<unsigned>();
    if (record.contains("last_number")) read.last_number = record.at("last_number").get<unsigned>();
    return read;
  } catch (const std::exception& e) {
    spdlog::warn("remote config: {} cannot be read ({}): the operator's file is in force", path.string(), e.what());
    return {};
  }
}

void RemoteConfigStore::write_in_force(const InForceRecord& record) const {
  json written{{"number", nullptr}, {"last_number", record.last_number}};
  if (record.number) written["number"] = *record.number;
  replace_owner_only(in_force_path(), written.dump() + "\n");
}

std::optional<StoredConfig> RemoteConfigStore::read_entry(unsigned number) const {
  const auto path = record_path(number);
  try {
    const auto bytes = read_if_present(path);
    if (!bytes) throw std::runtime_error("it is not there");
    const auto record = json::parse(*bytes);
    if (record.at("number").get<unsigned>() != number) throw std::runtime_error("it holds the record of another number");
    StoredConfig stored;
    stored.number = number;
    stored.id = text_field(record, "id");
    const auto source = source_named(text_field(record, "source"));
    if (!source) throw std::runtime_error("its source is none of mqtt, http, cli");
    stored.source = *source;
    stored.by = text_field(record, "by");
    stored.applied_at = text_field(record, "applied_at");
    stored.replaced_file = text_field(record, "replaced_file");
    stored.replaced_sha256 = text_field(record, "replaced_sha256");
    stored.replaced_known = record.contains("replaced_number");
    if (stored.replaced_known && !record.at("replaced_number").is_null())
      stored.replaced_number = record.at("replaced_number").get<unsigned>();
    stored.text_path = text_path(number);
    std::error_code error;
    if (!std::filesystem::is_regular_file(std::filesystem::symlink_status(stored.text_path, error)))
      throw std::runtime_error(fmt::format("its text {} is not there", stored.text_path.string()));
    return stored;
  } catch (const std::exception& e) {
    spdlog::warn("remote config: the record {} cannot be read ({}); remote config {} is skipped", path.string(), e.what(),
                 number);
    return std::nullopt;
  }
}

StoredConfig RemoteConfigStore::keep(std::string_view text, remote::Source source, std::string by,
                                     std::string replaced_file, std::string replaced_sha256,
                                     std::optional<unsigned> replaced_number, std::chrono::system_clock::time_point when) {
  make_directory();
  const auto numbers = numbers_in(directory_);
  const auto last = std::max(read_in_force().last_number, numbers.empty() ? 0u : numbers.front());
  StoredConfig stored{last + 1,
                      remote::change_id(text),
                      source,
                      std::move(by),
                      platform::utc_time_text(when),
                      std::move(replaced_file),
                      std::move(replaced_sha256),
                      replaced_number,
                      true,
                      text_path(last + 1)};
  // The text, then its record, then the record that puts it in force: a crash between two
  // leaves an entry nothing names, never a record in force without its text.
  replace_owner_only(stored.text_path, text);
  const json record{{"number", stored.number},
                    {"id", stored.id},
                    {"source", std::string(remote::source_name(stored.source))},
                    {"by", stored.by},
                    {"applied_at", stored.applied_at},
                    {"replaced_file", stored.replaced_file},
                    {"replaced_sha256", stored.replaced_sha256},
                    {"replaced_number", stored.replaced_number ? json(*stored.replaced_number) : json(nullptr)}};
  replace_owner_only(record_path(stored.number), record.dump(2) + "\n");
  write_in_force({stored.number, stored.number});
  forget_beyond_keep(stored.number);
  return stored;
}

// The newest `keep_` stay, and the one in force whatever its age. What cannot be removed
// is warned of, not thrown: the config was kept and is in force; the next keep tries again.
void RemoteConfigStore::forget_beyond_keep(std::optional<unsigned> in_force) const {
  const auto numbers = numbers_in(directory_);
  bool forgot = false;
  for (std::size_t i = keep_; i < numbers.size(); ++i) {
    if (numbers[i] == in_force) continue;
    // The record first: an entry whose text is left without it is skipped, and forgotten by
    // the next keep().
    for (const auto& path : {record_path(numbers[i]), text_path(numbers[i])}) {
      std::error_code error;
      std::filesystem::remove(path, error);
      if (error) spdlog::warn("remote config: cannot forget {}: {}", path.string(), error.message());
    }
    forgot = true;
  }
  if (!forgot) return;
  try {
    sync_directory(in_force_path());
  } catch (const std::system_error& e) {
    spdlog::warn("remote config: {}", e.what());
  }
}

void RemoteConfigStore::put_file_in_force() {
  std::error_code error;
  if (!std::filesystem::exists(directory_, error)) return;  // nothing was ever kept: the file is in force
  auto record = read_in_force();
  const auto numbers = numbers_in(directory_);
  record.last_number = std::max(record.last_number, numbers.empty() ? 0u : numbers.front());
  record.number.reset();
  write_in_force(record);
}

std::optional<StoredConfig> RemoteConfigStore::in_force() const {
  const auto record = read_in_force();
  if (!record.number) return std::nullopt;
  auto stored = read_entry(*record.number);
  if (!stored)
    spdlog::warn("remote config: {} names remote config {}, which cannot be read: the operator's file is in force",
                 in_force_path().string(), *record.number);
  return stored;
}

std::vector<StoredConfig> RemoteConfigStore::history() const {
  std::vector<StoredConfig> entries;
  for (const auto number : numbers_in(directory_))
    if (auto stored = read_entry(number)) entries.push_back(std::move(*stored));
  return entries;
}

std::string RemoteConfigStore::text(const StoredConfig& stored) const {
  try {
    if (auto bytes = read_if_present(stored.text_path)) return std::move(*bytes);
    throw std::runtime_error("it is not there");
  } catch (const std::exception& e) {
    throw std::runtime_error(fmt::format("remote config {}: {}: {}", stored.number, stored.text_path.string(), e.what()));
  }
}

void RemoteConfigStore::set_keep(unsigned keep) { keep_ = keep; }

}  // namespace unima::io
