// The frame readers' shared problem text and file opening; see frame_file_problem.hpp.
#include "drivers/frames/frame_file_problem.hpp"

#include <fcntl.h>

#include <algorithm>
#include <cerrno>
#include <cstdarg>
#include <cstdio>
#include <cstring>

#include "base/regular_file.hpp"

namespace ccdlane {

PgmFault FrameFileProblem::fail(PgmFault fault, const char* path, const char* format, ...) {
  const int n = std::snprintf(message_.data(), message_.size(), "%s: ", path);
  std::size_t used = std::min(static_cast<std::size_t>(std::max(n, 0)), message_.size() - 1);
  va_list args;
  va_start(args, format);
  const int m = std::vsnprintf(message_.data() + used, message_.size() - used, format, args);
  va_end(args);
  if (m > 0) used = std::min(used + static_cast<std::size_t>(m), message_.size() - 1);
  length_ = used;
  return fault;
}

PgmFault FrameFileProblem::open_regular(const char* path, UniqueFd& fd, struct stat& st) {
  // Without blocking: a FIFO in a frame's place must not hang the capture thread.
  fd = UniqueFd(open_regular_file(path, &st));
  if (fd.get() == -ENOENT) return fail(PgmFault::missing, path, "missing (no such file)");
  if (fd.get() == -EINVAL) return fail(PgmFault::unreadable, path, "not a regular file");
  if (fd.get() < 0) return fail(PgmFault::unreadable, path, "cannot open: %s", std::strerror(-fd.get()));
  return PgmFault::none;
}

}  // namespace ccdlane
