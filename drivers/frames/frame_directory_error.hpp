// The error of a frame directory that cannot be used at all (read or written).
#pragma once

#include <stdexcept>

namespace ccdlane {

// No frames.csv, no file or t_ns column, a directory that cannot be written. The message
// names the file and the reason.
class FrameDirectoryError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace ccdlane
