// fstat on the opened fd, not stat before open: what is checked is what is read.
#include "base/regular_file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "base/unique_fd.hpp"

namespace ccdlane {

int open_regular_file(const char* path, struct stat* st) {
  UniqueFd fd(::open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC));
  if (!fd) return -errno;
  struct stat s {};
  if (::fstat(fd.get(), &s) != 0) return -errno;
  if (!S_ISREG(s.st_mode)) return -EINVAL;
  const int flags = ::fcntl(fd.get(), F_GETFL);
  if (flags < 0 || ::fcntl(fd.get(), F_SETFL, flags & ~O_NONBLOCK) != 0) return -errno;
  if (st) *st = s;
  return fd.release();
}

int read_regular_file(const std::string& path, std::size_t max_bytes, std::string& out) {
  struct stat st {};
  const int rc = open_regular_file(path.c_str(), &st);
  if (rc < 0) return rc;
  const UniqueFd fd(rc);
  if (static_cast<std::size_t>(st.st_size) > max_bytes) return -EFBIG;
  out.clear();
  out.reserve(static_cast<std::size_t>(st.st_size));
  char chunk[65536];
  for (;;) {  // to the end, not to st_size: a file that grows meanwhile is still bounded
    const ssize_t n = ::read(fd.get(), chunk, sizeof chunk);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) return -errno;
    if (n == 0) return 0;
    if (out.size() + static_cast<std::size_t>(n) > max_bytes) return -EFBIG;
    out.append(chunk, static_cast<std::size_t>(n));
  }
}

const char* regular_file_error(int rc) {
  if (rc == -EINVAL) return "not a regular file";
  if (rc == -EFBIG) return "too large";
  return std::strerror(-rc);
}

}  // namespace ccdlane
