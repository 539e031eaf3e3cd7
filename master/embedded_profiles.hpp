#pragma once
// The text of master/profiles/*.yaml, compiled into the binary (see cmake/embed_yaml.cmake).

#include <string_view>
#include <vector>

namespace unima::master {

struct EmbeddedProfile {
  std::string_view file_name;
  std::string_view yaml_text;
};

const std::vector<EmbeddedProfile>& embedded_profiles();

}  // namespace unima::master
