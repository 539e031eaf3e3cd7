#pragma once
// What a technician needs to hear when yaml-cpp refuses a file's syntax. yaml-cpp says
// "illegal map value" or "end of map not found" for a line indented by a tab or by the
// wrong number of spaces, often at a neighbouring line's mark; this looks at the text
// itself and names the line that is wrong, and why. The one place that explains
// yaml-cpp's syntax errors (banks/yaml_document.hpp asks it for every data and config file).

#include <string>
#include <string_view>

namespace unima::banks {

struct YamlSyntaxError {
  int line = 0;    // 1-based, as in "file:line:column"
  int column = 0;  // 1-based
  std::string message;
};

/// `text` was refused by yaml-cpp with `parser_message` at the 0-based `line`, `column`.
/// A tab in a line's indentation, or a line indented unlike any line it could belong to,
/// at or before the line after the mark, is explained at its own position; any other error
/// is yaml-cpp's, at its mark.
YamlSyntaxError explain_yaml_syntax_error(std::string_view text, int line, int column, std::string_view parser_message);

}  // namespace unima::banks
