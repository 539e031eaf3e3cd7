#include "io/tls_context.hpp"

#include <sys/stat.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <mutex>
#include <optional>
#include <vector>

namespace unima::io {

namespace {

// A file as it was when its context was built: a rewrite, a rename over it or a touch
// makes another.
struct FileIdentity {
  dev_t device = 0;
  ino_t inode = 0;
  off_t size = 0;
  std::int64_t modified_ns = 0;
  bool operator==(const FileIdentity&) const = default;
};

std::optional<FileIdentity> identify(const std::string& path) {
  if (path.empty()) return FileIdentity{};
  struct stat status {};
  if (::stat(path.c_str(), &status) != 0) return std::nullopt;
  return FileIdentity{status.st_dev, status.st_ino, status.st_size,
                      std::int64_t{status.st_mtim.tv_sec} * 1'000'000'000 + status.st_mtim.tv_nsec};
}

using Identities = std::array<std::optional<FileIdentity>, 3>;

Identities identify(const tls::TlsFiles& files) { return {identify(files.certificate), identify(files.key), identify(files.ca)}; }

std::shared_ptr<asio::ssl::context> build(const tls::TlsFiles& files, std::string_view section) {
  // Asio's context takes the handle over and frees it.
  return std::make_shared<asio::ssl::context>(tls::load_server_credentials(files, section).release());
}

struct Prepared {
  tls::TlsFiles files;
  Identities identities;
  std::shared_ptr<asio::ssl::context> context;
};

constexpr std::size_t most_prepared = 4;
std::mutex prepared_mutex;
std::vector<Prepared> prepared;  // oldest first
std::size_t taken = 0;

void prepare(const tls::TlsFiles& files, std::string_view section) {
  // Identified before the read: a file changed meanwhile makes the context stale, never
  // the stale context fresh.
  auto identities = identify(files);
  std::shared_ptr<asio::ssl::context> context;
  try {
    context = build(files, section);
  } catch (const std::exception&) {
    return;  // the stage reads them again and says what is wrong
  }
  const std::lock_guard lock(prepared_mutex);
  std::erase_if(prepared, [&](const Prepared& p) { return p.files == files; });
  prepared.push_back({files, identities, std::move(context)});
  if (prepared.size() > most_prepared) prepared.erase(prepared.begin());
}

}  // namespace

tls::TlsFiles modbus_tls_files(const config::TlsSlaveConfig& tls) { return {tls.certificate, tls.key, tls.ca}; }

tls::TlsFiles http_tls_files(const config::HttpTlsConfig& tls) { return {tls.certificate, tls.key, {}}; }

std::shared_ptr<asio::ssl::context> make_server_tls_context(const tls::TlsFiles& files, std::string_view section) {
  std::optional<Prepared> ready;
  {
    const std::lock_guard lock(prepared_mutex);
    const auto found = std::find_if(prepared.begin(), prepared.end(), [&](const Prepared& p) { return p.files == files; });
    if (found != prepared.end()) {
      ready = std::move(*found);
      prepared.erase(found);
    }
  }
  if (ready && ready->identities == identify(files)) {
    const std::lock_guard lock(prepared_mutex);
    ++taken;
    return std::move(ready->context);
  }
  return build(files, section);
}

std::size_t prepared_tls_contexts_taken() {
  const std::lock_guard lock(prepared_mutex);
  return taken;
}

void prepare_server_tls_contexts(const config::Config& next) {
  if (next.modbus.tls) prepare(modbus_tls_files(*next.modbus.tls), "modbus.tls");
  if (next.http && next.http->tls) prepare(http_tls_files(*next.http->tls), "http.tls");
}

}  // namespace unima::io
