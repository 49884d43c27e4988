// Whether an output would write over an input: a tool that writes where it reads (replay's
// --overlay into its own recording, --out onto one of its frames) destroys what it reads.
#pragma once

#include <string>

namespace ccdlane {

// True when `output` is `input` (the same file, a hard link to it included) or lies
// inside the directory `input`, after resolving "..", symlinks and relative paths of
// whatever part of each exists. Neither needs to exist.
bool lies_within(const std::string& output, const std::string& input);

}  // namespace ccdlane
