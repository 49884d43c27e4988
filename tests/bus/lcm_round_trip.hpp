// Publishes lane and status messages through an LcmPublisher and checks what a
// subscriber on the same bus decodes (shared by the memq:// and udpm:// tests).
#pragma once

#include <lcm/lcm-cpp.hpp>

#include "bus/lcm_publisher.hpp"

namespace ccdlane::test {

// `subscriber` may be the publisher's own bus object (memq:// needs that). Also checks
// that publishing after the first message uses no operator new.
void lcm_round_trip(LcmPublisher& publisher, lcm::LCM& subscriber);

}  // namespace ccdlane::test
