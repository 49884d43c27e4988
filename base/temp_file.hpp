// The temporary file of an atomic write ("write beside, then rename over"): created new
// under a name nobody chose, so that a symlink or a user's file at a guessable
// "<path>.tmp" is never followed, truncated or renamed away.
#pragma once

#include <cstddef>

namespace ccdlane {

// Creates "<path>.tmp.XXXXXX" (mkostemp: O_CREAT|O_EXCL, so never an existing name and
// never through a symlink) in `path`'s directory, mode 0644, and writes its name into
// `tmp` (`size` bytes). The fd (close-on-exec), or -errno; -ENAMETOOLONG when the name
// does not fit. Allocates nothing.
int create_temp_beside(const char* path, char* tmp, std::size_t size);

}  // namespace ccdlane
