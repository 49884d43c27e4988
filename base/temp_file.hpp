// The temporary file of an atomic write ("write beside, then rename over"): created new
// under a name nobody chose, so that a symlink or a user's file at a guessable
// "<path>.tmp" is never followed, truncated or renamed away.
#pragma once

#include <cstddef>
#include <string>

namespace ccdlane {

// Creates "<path>.tmp.XXXXXX" (mkostemp: O_CREAT|O_EXCL, so never an existing name and
// never through a symlink) in `path`'s directory, mode 0644, and writes its name into
// `tmp` (`size` bytes). The fd (close-on-exec), or -errno; -ENAMETOOLONG when the name
// does not fit. Allocates nothing.
int create_temp_beside(const char* path, char* tmp, std::size_t size);

// The same for writers that open their temporary by name (a stream, lcm::LogFile): the
// file is created as above and closed, and its name returned; "" with errno set when it
// cannot be. The name was new and unguessable, so reopening it follows no one's link.
std::string new_temp_beside(const std::string& path);

}  // namespace ccdlane
