// A V4L2 device node held by a move-only fd, and the one ioctl wrapper every V4L2 call
// goes through: it returns -errno and never logs (the caller knows the context).
#pragma once

#include "base/unique_fd.hpp"

namespace ccdlane {

class V4l2Device {
 public:
  V4l2Device() = default;
  // Takes an already-open node (tests, a descriptor passed by a supervisor).
  explicit V4l2Device(UniqueFd fd) : fd_(std::move(fd)) {}

  // Opens `path` non-blocking (frames are waited for with poll()). 0 or -errno. The node
  // need not be a character device: a FUSE-served file speaks V4L2 just as well.
  int open(const char* path);
  void close() { fd_.reset(); }
  bool is_open() const { return fd_.valid(); }
  int fd() const { return fd_.get(); }

  // ioctl(2), retried on EINTR: its result (>= 0) or -errno.
  int ioctl(unsigned long request, void* arg) const;
  template <class T>
  int ioctl(unsigned long request, T* arg) const {
    return ioctl(request, static_cast<void*>(arg));
  }

 private:
  UniqueFd fd_;
};

}  // namespace ccdlane
