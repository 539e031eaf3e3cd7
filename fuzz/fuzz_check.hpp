#pragma once
// What a fuzz target asserts beyond "does not crash": a broken invariant aborts with the
// condition and the place, so libFuzzer keeps the input as a crash like any other finding.
// Not assert(): it must hold in every build type, NDEBUG or not.

#include <cstdio>
#include <cstdlib>

#define FUZZ_CHECK(condition)                                                                \
  do {                                                                                       \
    if (!(condition)) {                                                                      \
      std::fprintf(stderr, "%s:%d: invariant broken: %s\n", __FILE__, __LINE__, #condition); \
      std::abort();                                                                          \
    }                                                                                        \
  } while (false)
