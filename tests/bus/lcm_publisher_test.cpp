// The publisher on an in-process LCM bus (memq://): what arrives decodes to what was
// sent, and publishing allocates nothing. (udpm://: lcm_publisher_bus_test.cpp.)
#include "bus/lcm_publisher.hpp"

#include <cmath>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

#include "bus/lane_message.hpp"
#include "daemon/allocation_counter.hpp"
#include "tests/bus/lcm_round_trip.hpp"

namespace ccdlane {
namespace {

TEST(LcmPublisher, ChannelsFollowThePrefix) {
  LcmConfig config;
  config.url = "memq://";
  config.prefix = "CAR7_";
  LcmPublisher p(config);
  EXPECT_EQ(p.lanes_channel(), "CAR7_LANES");
  EXPECT_EQ(p.status_channel(), "CAR7_STATUS");
}

TEST(LcmPublisher, RoundTripOverMemq) {
  LcmConfig config;
  config.url = "memq://";
  LcmPublisher publisher(config);
  test::lcm_round_trip(publisher, publisher.bus());
}

TEST(LcmPublisher, StatusTextsLongerThanReservedAreRefused) {
  LcmConfig config;
  config.url = "memq://";
  LcmPublisher publisher(config);
  status_t status{};
  status.camera_problem.assign(kStatusTextMax + 1, 'x');
  EXPECT_FALSE(publisher.publish_status(status));
}

TEST(LcmPublisher, AnUnusableUrlIsOneClearError) {
  LcmConfig config;
  config.url = "nosuchprovider://x";
  try {
    LcmPublisher p(config);
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "lcm: cannot open the bus \"nosuchprovider://x\" ([lcm] url)");
  }
}

}  // namespace
}  // namespace ccdlane
