// What the PGM/PPM and PNG frame readers share: the one-line problem naming the file
// ("<path>: <reason>", in a fixed buffer), and opening a frame file for reading with the
// faults every format has (missing, unreadable, not a regular file). Allocates nothing.
#pragma once

#include <sys/stat.h>

#include <array>
#include <cstddef>
#include <string_view>

#include "base/unique_fd.hpp"
#include "drivers/frames/pgm_fault.hpp"

namespace ccdlane {

class FrameFileProblem {
 public:
  // "<path>: <reason>" of the last fault, valid until the next call.
  std::string_view error() const { return {message_.data(), length_}; }

  // Records "<path>: <formatted reason>" (cut to the buffer) and returns `fault`.
  PgmFault fail(PgmFault fault, const char* path, const char* format, ...) __attribute__((format(printf, 4, 5)));

  // A read succeeded: error() is empty.
  void clear_problem() { length_ = 0; }

  // Opens `path` read-only into `fd` and stats it into `st`: none, or the fault (recorded)
  // when it is missing, cannot be opened or stat'ed, or is not a regular file.
  PgmFault open_regular(const char* path, UniqueFd& fd, struct stat& st);

 private:
  std::array<char, 512> message_{};
  std::size_t length_ = 0;
};

}  // namespace ccdlane
