#pragma once
// The text of banks/tables/*.yaml, compiled into the binary (see cmake/embed_yaml.cmake).

#include <string_view>
#include <vector>

namespace unima::banks {

struct EmbeddedTable {
  std::string_view file_name;
  std::string_view yaml_text;
};

const std::vector<EmbeddedTable>& embedded_tables();

}  // namespace unima::banks
