// mkostemp gives 0600; the files written so (frames, overlays, tables, the state file)
// are meant to be read by others, as they were when written under their own name.
#include "base/temp_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>

namespace ccdlane {

int create_temp_beside(const char* path, char* tmp, std::size_t size) {
  const int n = std::snprintf(tmp, size, "%s.tmp.XXXXXX", path);
  if (n < 0 || static_cast<std::size_t>(n) >= size) return -ENAMETOOLONG;
  const int fd = ::mkostemp(tmp, O_CLOEXEC);
  if (fd < 0) return -errno;
  if (::fchmod(fd, 0644) != 0) {
    const int e = errno;
    ::close(fd);
    ::unlink(tmp);
    return -e;
  }
  return fd;
}

std::string new_temp_beside(const std::string& path) {
  std::string tmp(path.size() + 16, '\0');
  const int fd = create_temp_beside(path.c_str(), tmp.data(), tmp.size());
  if (fd < 0) {
    errno = -fd;
    return "";
  }
  ::close(fd);
  tmp.resize(path.size() + 11);  // ".tmp.XXXXXX"
  return tmp;
}

}  // namespace ccdlane
