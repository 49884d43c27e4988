// unshare(2) and the loopback bring-up, without shelling out.
#include "tests/drivers/camera/private_namespace.hpp"

#include <net/if.h>
#include <sched.h>
#include <sys/ioctl.h>
#include <sys/mount.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace ccdlane::test {

std::string enter_private_mount_namespace() {
  if (unshare(CLONE_NEWNS) != 0)
    return std::string("cannot enter a private mount namespace (needs root): ") + std::strerror(errno);
  // Without this, mounts would still propagate back to the host's shared mounts.
  if (mount(nullptr, "/", nullptr, MS_REC | MS_PRIVATE, nullptr) != 0)
    return std::string("cannot make mounts private: ") + std::strerror(errno);
  return "";
}

std::string enter_private_network_namespace() {
  if (unshare(CLONE_NEWNET) != 0)
    return std::string("cannot enter a private network namespace (needs root): ") + std::strerror(errno);
  const int s = socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  if (s < 0) return std::string("socket: ") + std::strerror(errno);
  ifreq ifr{};
  std::strncpy(ifr.ifr_name, "lo", IFNAMSIZ - 1);
  int r = ioctl(s, SIOCGIFFLAGS, &ifr);
  if (r == 0) {
    ifr.ifr_flags = static_cast<short>(ifr.ifr_flags | IFF_UP);
    r = ioctl(s, SIOCSIFFLAGS, &ifr);
  }
  const int e = errno;
  close(s);
  if (r != 0) return std::string("cannot bring loopback up: ") + std::strerror(e);
  return "";
}

}  // namespace ccdlane::test
