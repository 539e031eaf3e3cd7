#pragma once
// The front page's files (web/*.html, *.css, *.js), compiled into the binary (see
// cmake/embed_yaml.cmake), and what the HTTP server needs to serve one.

#include <optional>
#include <string_view>
#include <vector>

namespace unima::web {

struct PageFile {
  std::string_view file_name;  // "index.html"
  std::string_view text;
};

const std::vector<PageFile>& page_files();

struct ServedFile {
  std::string_view content_type;
  std::string_view text;
};

/// The file for a request path: "/" is index.html, "/panel.js" is panel.js; nullopt for
/// anything else (no directories, no other names).
std::optional<ServedFile> served_file(std::string_view path);

}  // namespace unima::web
