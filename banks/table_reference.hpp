#pragma once
// The English reference of every register table, in Markdown: docs/registers.md is this
// text (`unima-bridge tables > docs/registers.md`), and a test keeps the two equal.

#include <string>

namespace unima::banks {

std::string tables_markdown();

}  // namespace unima::banks
