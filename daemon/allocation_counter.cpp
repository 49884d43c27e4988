// Replaces the global operator new/delete with ones that count: per thread always, and
// process-wide while armed. The one replacement in the project (a program can have only
// one): linked into ccdlaned, its tests, and, through tests/support, every test that
// proves "no allocation". Replacing operator new is a whole-program decision.
//
// Only operator new is counted, not malloc: the daemon's own code and the C++ libraries
// allocate through new; C libraries underneath (liblcm, libsystemd, glibc) call malloc
// directly and are not seen here (glibc 2.34+ has no malloc hooks to count them with).
// Their steady-state paths were checked once by hand: gdb breakpoints on malloc, calloc
// and realloc in a running ccdlaned (60 fps, udpm publishing, sd_notify WATCHDOG and
// STATUS) saw no call in 4 s, nor during the shutdown that followed.
#include "daemon/allocation_counter.hpp"

#include <atomic>
#include <cstdlib>
#include <new>

namespace ccdlane::allocation_counter {
namespace {
std::atomic<bool> g_counting{false};
std::atomic<std::uint64_t> g_count{0};
thread_local std::uint64_t t_count = 0;

void count_one() noexcept {
  ++t_count;
  if (g_counting.load(std::memory_order_relaxed)) g_count.fetch_add(1, std::memory_order_relaxed);
}

void* allocate(std::size_t size) {
  count_one();
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}

void* allocate_aligned(std::size_t size, std::align_val_t alignment) {
  count_one();
  const auto a = static_cast<std::size_t>(alignment);
  // aligned_alloc wants a size that is a multiple of the alignment.
  const std::size_t rounded = ((size == 0 ? 1 : size) + a - 1) / a * a;
  if (void* p = std::aligned_alloc(a, rounded)) return p;
  throw std::bad_alloc();
}
}  // namespace

void start_counting() {
  g_count.store(0, std::memory_order_relaxed);
  g_counting.store(true, std::memory_order_release);
}
void stop_counting() { g_counting.store(false, std::memory_order_release); }
std::uint64_t count() { return g_count.load(std::memory_order_relaxed); }
std::uint64_t in_this_thread() { return t_count; }
void note_allocation() { count_one(); }

}  // namespace ccdlane::allocation_counter

using ccdlane::allocation_counter::allocate;
using ccdlane::allocation_counter::allocate_aligned;

void* operator new(std::size_t size) { return allocate(size); }
void* operator new[](std::size_t size) { return allocate(size); }
void* operator new(std::size_t size, const std::nothrow_t&) noexcept {
  try {
    return allocate(size);
  } catch (...) {
    return nullptr;
  }
}
void* operator new[](std::size_t size, const std::nothrow_t&) noexcept {
  try {
    return allocate(size);
  } catch (...) {
    return nullptr;
  }
}
void* operator new(std::size_t size, std::align_val_t a) { return allocate_aligned(size, a); }
void* operator new[](std::size_t size, std::align_val_t a) { return allocate_aligned(size, a); }
void* operator new(std::size_t size, std::align_val_t a, const std::nothrow_t&) noexcept {
  try {
    return allocate_aligned(size, a);
  } catch (...) {
    return nullptr;
  }
}
void* operator new[](std::size_t size, std::align_val_t a, const std::nothrow_t&) noexcept {
  try {
    return allocate_aligned(size, a);
  } catch (...) {
    return nullptr;
  }
}

void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, std::align_val_t, const std::nothrow_t&) noexcept { std::free(p); }
