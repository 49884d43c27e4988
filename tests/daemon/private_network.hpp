// Moves the calling test process into a private network namespace with a loopback
// interface and a multicast route: a hermetic LCM udpm bus (platform-notes.md).
#pragma once

#include <string>

namespace ccdlane::test {

// LCM's default udpm bus; inside the private namespace, each test's own.
inline const std::string kBusUrl = "udpm://239.255.76.67:7667?ttl=0";

// "" on success (threads and children created afterwards share the namespace), else
// why not, for GTEST_SKIP (not root, no unshare). Call before starting any thread.
std::string enter_private_network();

}  // namespace ccdlane::test
