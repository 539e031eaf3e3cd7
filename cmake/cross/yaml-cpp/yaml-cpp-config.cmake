# yaml-cpp for a cross build (toolchains/debian-cross.cmake says why): the target's shared
# library from libyaml-cpp0.7:<arch>, the headers from the host's libyaml-cpp-dev, which
# must be the same version (scripts/package.sh checks it).
find_library(UNIMA_YAML_CPP_LIBRARY NAMES libyaml-cpp.so.0.7 PATHS /usr/lib/${CMAKE_LIBRARY_ARCHITECTURE} NO_DEFAULT_PATH)
if(NOT UNIMA_YAML_CPP_LIBRARY OR NOT EXISTS /usr/include/yaml-cpp/yaml.h)
  set(yaml-cpp_FOUND FALSE)
  set(yaml-cpp_NOT_FOUND_MESSAGE
      "needs libyaml-cpp0.7:<target arch> and the host's libyaml-cpp-dev (scripts/package.sh installs both)")
  return()
endif()
if(NOT TARGET yaml-cpp)
  add_library(yaml-cpp SHARED IMPORTED)
  # Debian's cross compilers search /usr/include already: no include directory to add.
  set_target_properties(yaml-cpp PROPERTIES IMPORTED_LOCATION ${UNIMA_YAML_CPP_LIBRARY})
endif()
set(yaml-cpp_FOUND TRUE)
