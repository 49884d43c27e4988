// Counts the C allocator too (malloc & co., where Eigen's allocations land), for the
// programs and static libraries of a test linked with -Wl,--wrap=malloc,... (the
// ccdlane_malloc_counter target adds the flags). Feeds the counter of allocation_counter.
#include <cstddef>

#include "tests/support/allocation_counter.hpp"

extern "C" {
void* __real_malloc(std::size_t);
void* __real_calloc(std::size_t, std::size_t);
void* __real_realloc(void*, std::size_t);
int __real_posix_memalign(void**, std::size_t, std::size_t);
void* __real_aligned_alloc(std::size_t, std::size_t);

void* __wrap_malloc(std::size_t n) {
  ccdlane::test::note_allocation();
  return __real_malloc(n);
}
void* __wrap_calloc(std::size_t n, std::size_t size) {
  ccdlane::test::note_allocation();
  return __real_calloc(n, size);
}
void* __wrap_realloc(void* p, std::size_t n) {
  ccdlane::test::note_allocation();
  return __real_realloc(p, n);
}
int __wrap_posix_memalign(void** p, std::size_t align, std::size_t n) {
  ccdlane::test::note_allocation();
  return __real_posix_memalign(p, align, n);
}
void* __wrap_aligned_alloc(std::size_t align, std::size_t n) {
  ccdlane::test::note_allocation();
  return __real_aligned_alloc(align, n);
}
}
