// unshare(CLONE_NEWNET) affects only the calling thread, which is why it must come
// before the test starts threads; `ip` then configures the new namespace it inherits.
#include "tests/daemon/private_network.hpp"

#include <sched.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>

namespace ccdlane::test {

std::string enter_private_network() {
  if (geteuid() != 0) return "needs root for a private network namespace";
  if (unshare(CLONE_NEWNET) != 0) return std::string("unshare(CLONE_NEWNET): ") + std::strerror(errno);
  if (std::system("ip link set lo up && ip route add 224.0.0.0/4 dev lo") != 0)
    return "could not set up loopback multicast in the private namespace (ip link/route)";
  return "";
}

}  // namespace ccdlane::test
