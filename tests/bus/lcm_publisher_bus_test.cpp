// The publisher on a real multicast bus (udpm://), hermetic: the test process moves
// into its own network namespace with only a loopback and a multicast route.
#include <gtest/gtest.h>

#include "bus/lcm_publisher.hpp"
#include "tests/bus/lcm_round_trip.hpp"
#include "tests/daemon/private_network.hpp"

namespace ccdlane {
namespace {

TEST(LcmPublisherBus, RoundTripOverUdpmInAPrivateNetwork) {
  if (const std::string why = test::enter_private_network(); !why.empty()) GTEST_SKIP() << why;
  LcmConfig config;
  config.url = "udpm://239.255.76.67:7667?ttl=0";
  LcmPublisher publisher(config);
  lcm::LCM subscriber(config.url);
  ASSERT_TRUE(subscriber.good());
  test::lcm_round_trip(publisher, subscriber);
}

}  // namespace
}  // namespace ccdlane
