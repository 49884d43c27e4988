// The bus thread: on an in-process bus (memq://), one thread handles LCM for every
// subscriber: a vehicle state published from another thread reaches the listener, a
// status from another instance reaches the publisher's watch (taken once), and stop()
// returns within its handling timeout.
#include "daemon/bus_thread.hpp"

#include <chrono>
#include <thread>
#include <vector>

#include <ccdlane/vehicle_state_t.hpp>
#include <gtest/gtest.h>

#include "bus/channels.hpp"
#include "bus/lcm_publisher.hpp"
#include "bus/vehicle_state_listener.hpp"

namespace ccdlane {
namespace {

using Clock = std::chrono::steady_clock;

template <typename Done>
bool wait_for(Done done) {
  const auto deadline = Clock::now() + std::chrono::seconds(10);
  while (!done()) {
    if (Clock::now() > deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  return true;
}

TEST(BusThread, FeedsTheVehicleStateListenerAndTheOtherInstanceWatch) {
  LcmPublisher publisher(LcmConfig{"memq://", "CCDLANE_", false, ""});
  publisher.set_instance("here:1");
  publisher.watch_for_other_instances();
  lcm_t* lcm = publisher.bus().getUnderlyingLCM();
  VehicleStateListener vehicle(lcm, channel_name("CCDLANE_", Channel::vehicle));
  BusThread bus(lcm);
  bus.start();

  vehicle_state_t m{};
  m.speed_mps = 21.0;
  m.turn_indicator = vehicle_state_t::TURN_INDICATOR_RIGHT;
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(m.getEncodedSize()));
  m.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  ASSERT_EQ(lcm_publish(lcm, "CCDLANE_VEHICLE", bytes.data(), static_cast<unsigned>(bytes.size())), 0);
  ASSERT_TRUE(wait_for([&] { return vehicle.received() == 1; })) << "taken without anyone else handling the bus";
  ASSERT_TRUE(vehicle.latest());
  EXPECT_EQ(vehicle.latest()->speed_mps, 21.0);
  EXPECT_EQ(vehicle.latest()->indicator, TurnIndicator::right);

  status_t own{}, other{};
  own.instance = "here:1";
  other.instance = "there:2";
  ASSERT_TRUE(publisher.publish_status(own));
  ASSERT_TRUE(publisher.publish_status(other));
  const char* seen = nullptr;
  ASSERT_TRUE(wait_for([&] { return (seen = publisher.take_other_instance()) != nullptr; }));
  EXPECT_STREQ(seen, "there:2");
  ASSERT_TRUE(publisher.publish_status(other));
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  EXPECT_EQ(publisher.take_other_instance(), nullptr) << "said once";

  bus.stop();
  EXPECT_EQ(bus.errors(), 0u);
}

}  // namespace
}  // namespace ccdlane
