#include "web/page_files.hpp"

namespace unima::web {

namespace {

std::string_view content_type_of(std::string_view name) {
  if (name.ends_with(".html")) return "text/html; charset=utf-8";
  if (name.ends_with(".css")) return "text/css; charset=utf-8";
  if (name.ends_with(".js")) return "text/javascript; charset=utf-8";
  return "application/octet-stream";
}

}  // namespace

std::optional<ServedFile> served_file(std::string_view path) {
  if (path == "/") path = "/index.html";
  if (!path.starts_with('/')) return std::nullopt;
  path.remove_prefix(1);
  for (const auto& file : page_files())
    if (file.file_name == path) return ServedFile{content_type_of(file.file_name), file.text};
  return std::nullopt;
}

}  // namespace unima::web
