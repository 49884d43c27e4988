// The fuzz targets' one assertion: a failed property aborts with its text, so that
// libFuzzer keeps the input, in every build (NDEBUG or not).
#pragma once

#include <cstdio>
#include <cstdlib>

#define FUZZ_CHECK(condition)                                      \
  do {                                                             \
    if (!(condition)) {                                            \
      std::fprintf(stderr, "fuzz check failed: %s\n", #condition); \
      std::abort();                                                \
    }                                                              \
  } while (0)
