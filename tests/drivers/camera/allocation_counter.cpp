// Replaces the global operator new (and, without sanitizers, malloc) in the test program
// to count allocations per thread. A thread_local of trivial type in the executable lives
// in static TLS, so counting itself never allocates or recurses.
#include "tests/drivers/camera/allocation_counter.hpp"

#include <cstdlib>
#include <new>

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define CCDLANE_COUNT_MALLOC 0
#else
#define CCDLANE_COUNT_MALLOC 1
#endif

namespace {
thread_local std::uint64_t t_allocations = 0;
}

#if CCDLANE_COUNT_MALLOC
extern "C" {
void* __libc_malloc(std::size_t);
void* __libc_calloc(std::size_t, std::size_t);
void* __libc_realloc(void*, std::size_t);

void* malloc(std::size_t n) {
  ++t_allocations;
  return __libc_malloc(n);
}
void* calloc(std::size_t n, std::size_t m) {
  ++t_allocations;
  return __libc_calloc(n, m);
}
void* realloc(void* p, std::size_t n) {
  ++t_allocations;
  return __libc_realloc(p, n);
}
}
#endif

void* operator new(std::size_t n) {
#if !CCDLANE_COUNT_MALLOC
  ++t_allocations;
#endif
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t n) { return operator new(n); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }

namespace ccdlane::test {
std::uint64_t thread_allocations() { return t_allocations; }
bool counts_malloc() { return CCDLANE_COUNT_MALLOC != 0; }
}  // namespace ccdlane::test
