// Puts the test program in private Linux namespaces before any thread starts, so mounts
// (the FUSE fake camera) and network traffic (Aravis' GigE Vision on loopback) stay
// invisible to, and out of reach of, the rest of the machine.
#pragma once

#include <string>

namespace ccdlane::test {

// Each returns "" on success, else why not (tests then skip, saying so).
std::string enter_private_mount_namespace();
// A fresh network namespace with only the loopback interface, up.
std::string enter_private_network_namespace();

}  // namespace ccdlane::test
