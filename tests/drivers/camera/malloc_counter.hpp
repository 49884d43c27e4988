// Counts malloc/calloc/realloc calls made by the calling thread, C++ operator new (which
// calls malloc) and C libraries (glib's g_malloc inside Aravis) alike, so a test can prove
// a capture thread allocates nothing while other threads (a fake device's server, Aravis'
// receive thread) go about their business. tests/support/allocation_counter counts only
// operator new; this one also sees what C libraries called on our thread do.
#pragma once

#include <cstdint>

namespace ccdlane::test {

// False under sanitizers, which own malloc: tests needing the count skip, saying so.
bool malloc_counting_available();
// malloc-family calls by this thread since it started.
std::uint64_t mallocs_in_this_thread();

}  // namespace ccdlane::test
