// Counts heap allocations made by the calling thread (global operator new, and malloc
// family where it can be interposed), to prove a capture path allocates nothing while
// other threads (a fake device, a library's receive thread) go about their business.
#pragma once

#include <cstdint>

namespace ccdlane::test {

// Allocations by this thread since the program started.
std::uint64_t thread_allocations();
// True when malloc/calloc/realloc are counted too, not only operator new (they are not
// under sanitizers, which own malloc).
bool counts_malloc();

}  // namespace ccdlane::test
