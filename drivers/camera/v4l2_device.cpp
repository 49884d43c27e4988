// The V4L2 node and its ioctl wrapper.
#include "drivers/camera/v4l2_device.hpp"

#include <fcntl.h>
#include <sys/ioctl.h>

#include <cerrno>

namespace ccdlane {

int V4l2Device::open(const char* path) {
  const int fd = ::open(path, O_RDWR | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) return -errno;
  fd_.reset(fd);
  return 0;
}

int V4l2Device::ioctl(unsigned long request, void* arg) const {
  int r;
  do {
    r = ::ioctl(fd_.get(), request, arg);
  } while (r < 0 && errno == EINTR);
  return r < 0 ? -errno : r;
}

}  // namespace ccdlane
