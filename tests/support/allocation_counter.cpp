// The tests' per-thread allocation count, from the project's one counting operator new
// (daemon/allocation_counter.cpp, compiled into this object library).
#include "tests/support/allocation_counter.hpp"

#include "daemon/allocation_counter.hpp"

namespace ccdlane::test {

std::size_t allocations_in_this_thread() { return static_cast<std::size_t>(allocation_counter::in_this_thread()); }

void note_allocation() { allocation_counter::note_allocation(); }

}  // namespace ccdlane::test
