// Counts heap allocations once the daemon is ready, to prove (and report in its status)
// that the steady state allocates nothing; also per thread, for tests.
#pragma once

#include <cstdint>

namespace ccdlane::allocation_counter {

// Defined next to the counting operator new (allocation_counter.cpp), which only
// ccdlaned and its tests link.

// From now on every operator new (any thread) is counted.
void start_counting();
void stop_counting();

// Allocations since start_counting().
std::uint64_t count();

// Allocations made by the calling thread since it began, counted whether armed or not
// (tests/support's AllocationScope is built on this).
std::uint64_t in_this_thread();

// Counts one allocation that did not come through operator new: for allocator wrappers
// (tests wrap malloc & co. at link time, tests/support/malloc_counter.cpp).
void note_allocation();

}  // namespace ccdlane::allocation_counter
