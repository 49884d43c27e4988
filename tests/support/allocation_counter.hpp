// Counts heap allocations made through operator new in this thread: tests use it to
// prove that a real-time path allocates nothing ("no allocation" shown, not claimed).
#pragma once

#include <cstddef>

namespace ccdlane::test {

// Allocations (operator new of any form; with malloc_counter also malloc & co.) made by
// the calling thread so far.
std::size_t allocations_in_this_thread();
void note_allocation();  // counts one (for the allocator wrappers)

// Counts the allocations made while it is alive, in this thread.
class AllocationScope {
 public:
  AllocationScope() : start_(allocations_in_this_thread()) {}
  std::size_t count() const { return allocations_in_this_thread() - start_; }

 private:
  std::size_t start_;
};

}  // namespace ccdlane::test
