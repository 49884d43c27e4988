// Interposes malloc, calloc and realloc in the test executable (forwarding to glibc's
// __libc_* entry points). The counter is a trivially-initialised thread_local of the
// executable, so it lives in static TLS: counting never allocates or recurses.
#include "tests/drivers/camera/malloc_counter.hpp"

#include <cstddef>

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define CCDLANE_COUNT_MALLOC 0
#else
#define CCDLANE_COUNT_MALLOC 1
#endif

namespace {
thread_local std::uint64_t t_mallocs = 0;
}

#if CCDLANE_COUNT_MALLOC
extern "C" {
void* __libc_malloc(std::size_t);
void* __libc_calloc(std::size_t, std::size_t);
void* __libc_realloc(void*, std::size_t);

void* malloc(std::size_t n) {
  ++t_mallocs;
  return __libc_malloc(n);
}
void* calloc(std::size_t n, std::size_t m) {
  ++t_mallocs;
  return __libc_calloc(n, m);
}
void* realloc(void* p, std::size_t n) {
  ++t_mallocs;
  return __libc_realloc(p, n);
}
}
#endif

namespace ccdlane::test {
bool malloc_counting_available() { return CCDLANE_COUNT_MALLOC != 0; }
std::uint64_t mallocs_in_this_thread() { return t_mallocs; }
}  // namespace ccdlane::test
