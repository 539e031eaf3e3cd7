# What keeps the build within minutes (issue 41; measured in docs/performance.md, "Build
# time"): the heavy headers precompiled once per family of targets, and ccache told how to
# cache the translation units that use them. CMAKE_DISABLE_PRECOMPILE_HEADERS=ON builds
# without them (clang-tidy, include-what-you-use).

# RelWithDebInfo, the build of the developers and of scripts/test.sh, keeps line tables
# only (-g1, after CMake's -g: the last level counts): backtraces, sanitizer reports and
# perf keep their files and lines, and the whole tree builds in a quarter less time (the
# full DWARF of -g is most of the assembler's work; docs/performance.md, "Build time").
# -DUNIMA_FULL_DEBUG_INFO=ON keeps -g, for gdb's local variables.
option(UNIMA_FULL_DEBUG_INFO "RelWithDebInfo with full debug info (-g) instead of line tables (-g1)" OFF)
if(NOT UNIMA_FULL_DEBUG_INFO)
  add_compile_options($<$<CONFIG:RelWithDebInfo>:-g1>)
endif()

# The test programs and their support libraries are compiled without optimisation (-O0,
# after CMake's -O2: the last level counts): they are half the tree's compile time and -O2
# costs them twice what -O0 does, while what they run is the libraries and the daemon, which
# keep -O2. -DUNIMA_OPTIMISE_TESTS=ON compiles them like the rest.
option(UNIMA_OPTIMISE_TESTS "Compile the test programs with the build type's optimisation" OFF)
function(unima_test_code target)
  if(NOT UNIMA_OPTIMISE_TESTS)
    target_compile_options(${target} PRIVATE $<$<CONFIG:RelWithDebInfo,Release,MinSizeRel>:-O0>)
  endif()
endfunction()

# Unity builds: each library and program compiles its sources in batches, so the headers
# every file of a folder includes (the STL, fmt, JSON, yaml-cpp) are parsed once a batch,
# not once a file. A file-local name (anonymous namespace, static) must then be unique
# within its library; a clash shows as a redefinition error. The test programs choose their
# own batches (tests/CMakeLists.txt). -DUNIMA_UNITY_BUILD=OFF compiles file by file.
option(UNIMA_UNITY_BUILD "Compile each library's sources in batches (unity build)" ON)
if(UNIMA_UNITY_BUILD)
  set(CMAKE_UNITY_BUILD ON)
  set(CMAKE_UNITY_BUILD_BATCH_SIZE 8)
endif()

# The Asio side (io/, app/): Asio comes first through platform/asio.hpp, which includes
# <utility> before it (Boost 1.74 with GCC 12 in C++20). unima_io precompiles them; the
# other Asio targets reuse its header (REUSE_FROM), so it is compiled once.
set(UNIMA_ASIO_PCH <platform/asio.hpp> <platform/asio_ssl.hpp> <spdlog/spdlog.h> <fmt/format.h>
                   <nlohmann/json.hpp> <string> <vector> <map> <memory> <functional> <chrono>)

# The test programs: GoogleTest and JSON, in every test file.
set(UNIMA_TEST_PCH <gtest/gtest.h> <nlohmann/json.hpp> <fmt/format.h> <string> <vector> <map> <memory>
                   <functional> <chrono> <filesystem>)

# ccache caches a translation unit built with a precompiled header only when it may ignore
# the header's __DATE__/__TIME__ and defines and trust a header written moments ago (ccache
# manual, "Precompiled headers"); said here so that no developer's ccache.conf has to.
if(CMAKE_CXX_COMPILER_LAUNCHER MATCHES "ccache" AND NOT CMAKE_CXX_COMPILER_LAUNCHER MATCHES "CCACHE_SLOPPINESS")
  set(CMAKE_CXX_COMPILER_LAUNCHER
      ${CMAKE_COMMAND} -E env "CCACHE_SLOPPINESS=pch_defines,time_macros,include_file_mtime,include_file_ctime"
      ${CMAKE_CXX_COMPILER_LAUNCHER})
endif()
