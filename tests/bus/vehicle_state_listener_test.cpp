// The vehicle state listener: messages published on an in-process bus (memq://) become
// the latest state; invalid ones are refused and counted; taking a message allocates
// nothing; a reader racing the writer never sees a torn state; a stale state gives no
// inputs; states beyond physical bounds are refused by cause, each cause logged once, and
// a gateway that sends only those, or falls silent, is at fault.
#include "bus/vehicle_state_listener.hpp"

#include <atomic>
#include <string>
#include <thread>
#include <vector>

#include <ccdlane/vehicle_state_t.hpp>
#include <gtest/gtest.h>

#include "base/clock.hpp"
#include "bus/channels.hpp"
#include "tests/support/allocation_counter.hpp"

namespace ccdlane {
namespace {

std::vector<std::uint8_t> encode(const vehicle_state_t& m) {
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(m.getEncodedSize()));
  m.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  return bytes;
}

vehicle_state_t message(double speed_mps, std::int8_t indicator, bool yaw = false, double yaw_rate = 0.0) {
  vehicle_state_t m{};
  m.utime = 1'700'000'000'000'000;
  m.speed_mps = speed_mps;
  m.has_yaw_rate = yaw;
  m.yaw_rate_radps = yaw_rate;
  m.turn_indicator = indicator;
  return m;
}

struct Bus {
  lcm_t* lcm = lcm_create("memq://");
  ~Bus() { lcm_destroy(lcm); }
  // memq:// delivers a message on the next handle, and drops one nobody subscribed to.
  void publish(const std::string& channel, const vehicle_state_t& m, bool subscribed = true) const {
    const auto bytes = encode(m);
    ASSERT_EQ(lcm_publish(lcm, channel.c_str(), bytes.data(), static_cast<unsigned>(bytes.size())), 0);
    if (subscribed) {
      ASSERT_GT(lcm_handle_timeout(lcm, 1000), 0);
    }
  }
};

TEST(VehicleStateListener, TakesTheLatestMessageOfItsChannel) {
  Bus bus;
  ASSERT_NE(bus.lcm, nullptr);
  const std::string channel = channel_name("CCDLANE_", Channel::vehicle);
  VehicleStateListener listener(bus.lcm, channel);
  EXPECT_FALSE(listener.latest()) << "nothing before the first message";

  bus.publish(channel, message(20.0, vehicle_state_t::TURN_INDICATOR_LEFT, true, 0.05));
  auto s = listener.latest();
  ASSERT_TRUE(s);
  EXPECT_EQ(s->utime, 1'700'000'000'000'000);
  EXPECT_EQ(s->speed_mps, 20.0);
  EXPECT_EQ(s->yaw_rate_radps, 0.05);
  EXPECT_EQ(s->indicator, TurnIndicator::left);
  EXPECT_GT(s->received_ns, 0);

  bus.publish(channel, message(22.5, vehicle_state_t::TURN_INDICATOR_NONE));
  s = listener.latest();
  EXPECT_EQ(s->speed_mps, 22.5);
  EXPECT_FALSE(s->yaw_rate_radps) << "has_yaw_rate false: no yaw rate";
  EXPECT_EQ(s->indicator, TurnIndicator::none);

  bus.publish("CCDLANE_OTHER", message(5.0, 0), false);  // another channel: not ours
  lcm_handle_timeout(bus.lcm, 10);
  EXPECT_EQ(listener.latest()->speed_mps, 22.5);
  EXPECT_EQ(listener.received(), 2u);
}

TEST(VehicleStateListener, InvalidMessagesAreRefusedAndCounted) {
  VehicleStateListener listener(nullptr, "");
  const auto good = encode(message(10.0, vehicle_state_t::TURN_INDICATOR_RIGHT));
  ASSERT_TRUE(listener.accept(good.data(), static_cast<int>(good.size()), 1));
  for (const vehicle_state_t& bad :
       {message(-1.0, 0), message(NAN, 0), message(10.0, 4), message(10.0, 0, true, INFINITY)}) {
    const auto bytes = encode(bad);
    EXPECT_FALSE(listener.accept(bytes.data(), static_cast<int>(bytes.size()), 2));
  }
  EXPECT_FALSE(listener.accept(good.data(), static_cast<int>(good.size()) - 3, 3)) << "truncated";
  EXPECT_EQ(listener.rejected(), 5u);
  EXPECT_EQ(listener.latest()->speed_mps, 10.0) << "the last good message stays";
  EXPECT_EQ(listener.latest()->indicator, TurnIndicator::right);
}

TEST(VehicleStateListener, StatesBeyondPhysicalBoundsAreRefusedByCauseAndLoggedOnce) {
  std::vector<std::string> lines;
  VehicleStateListener listener(nullptr, "CCDLANE_VEHICLE",
                                [&](LogLevel, const char*, const char* line) { lines.emplace_back(line); });
  const auto offer = [&](const vehicle_state_t& m) {
    const auto bytes = encode(m);
    return listener.accept(bytes.data(), static_cast<int>(bytes.size()), 1);
  };
  EXPECT_TRUE(offer(message(kMaxVehicleSpeedMps, 0, true, -kMaxVehicleYawRateRadps))) << "the bounds are allowed";
  EXPECT_TRUE(offer(message(0.0, vehicle_state_t::TURN_INDICATOR_BOTH, true, kMaxVehicleYawRateRadps)));
  for (const double speed : {70.01, 150.0, 300.0, 1e30, -0.0001, double{NAN}}) EXPECT_FALSE(offer(message(speed, 0)));
  for (const double yaw : {2.01, -1e30, double{NAN}}) EXPECT_FALSE(offer(message(20.0, 0, true, yaw)));
  EXPECT_TRUE(offer(message(20.0, 0, false, 1e30))) << "a yaw rate not reported is not looked at";
  for (const std::int8_t indicator : {std::int8_t{99}, std::int8_t{-1}, std::int8_t{4}})
    EXPECT_FALSE(offer(message(20.0, indicator)));
  vehicle_state_t other{};
  const auto other_bytes = encode(other);
  std::vector<std::uint8_t> wrong_hash = other_bytes;
  wrong_hash[0] ^= 0xff;
  EXPECT_FALSE(listener.accept(wrong_hash.data(), static_cast<int>(wrong_hash.size()), 1));
  EXPECT_EQ(listener.rejected(VehicleRefusal::speed), 6u);
  EXPECT_EQ(listener.rejected(VehicleRefusal::yaw_rate), 3u);
  EXPECT_EQ(listener.rejected(VehicleRefusal::indicator), 3u);
  EXPECT_EQ(listener.rejected(VehicleRefusal::undecodable), 1u);
  EXPECT_EQ(listener.rejected(), 13u);
  EXPECT_EQ(listener.received(), 3u);
  ASSERT_EQ(lines.size(), 4u) << "one line per cause";
  EXPECT_NE(lines[0].find("CCDLANE_VEHICLE: refused a vehicle_state_t for its speed (speed 70.01 m/s"),
            std::string::npos)
      << lines[0];
  EXPECT_NE(lines[1].find("for its yaw_rate"), std::string::npos) << lines[1];
  EXPECT_NE(lines[2].find("for its indicator"), std::string::npos) << lines[2];
  EXPECT_NE(lines[3].find("no vehicle_state_t"), std::string::npos) << lines[3];
  const GatewayCounters c = listener.counters(1, 500'000'000);
  EXPECT_EQ(c.taken, 3u);
  EXPECT_EQ(c.refused[static_cast<std::size_t>(VehicleRefusal::speed)], 6u);
}

TEST(VehicleStateListener, AGatewayIsAtFaultWhileItSendsOnlyRefusedStatesOrFellSilent) {
  Bus bus;
  ASSERT_NE(bus.lcm, nullptr);
  const std::string channel = channel_name("CCDLANE_", Channel::vehicle);
  VehicleStateListener listener(bus.lcm, channel, [](LogLevel, const char*, const char*) {});
  constexpr std::int64_t kMaxAge = 500'000'000;
  EXPECT_EQ(listener.gateway(monotonic_ns(), kMaxAge), GatewayState::none);
  EXPECT_TRUE(vehicle_inputs(listener, monotonic_ns(), kMaxAge).vehicle_ok) << "no gateway: the configured speed";

  bus.publish(channel, message(150.0, 0));
  EXPECT_EQ(listener.gateway(monotonic_ns(), kMaxAge), GatewayState::fault) << "only refused states";
  VehicleInputs in = vehicle_inputs(listener, monotonic_ns(), kMaxAge);
  EXPECT_FALSE(in.vehicle_ok);
  EXPECT_FALSE(in.speed_mps) << "150 m/s is not used";

  bus.publish(channel, message(25.0, 0));
  const std::int64_t good_at = monotonic_ns();
  EXPECT_EQ(listener.gateway(good_at, kMaxAge), GatewayState::ok);
  in = vehicle_inputs(listener, good_at, kMaxAge);
  EXPECT_TRUE(in.vehicle_ok);
  EXPECT_EQ(in.speed_mps, 25.0);

  bus.publish(channel, message(1e30, 0));  // refused, but the good state is still fresh
  EXPECT_EQ(listener.gateway(good_at + kMaxAge / 2, kMaxAge), GatewayState::ok);
  EXPECT_EQ(listener.gateway(good_at + 2 * kMaxAge, kMaxAge), GatewayState::fault) << "silent after good ones";
  EXPECT_FALSE(vehicle_inputs(listener, good_at + 2 * kMaxAge, kMaxAge).vehicle_ok);
}

TEST(VehicleStateListener, TakingAndReadingAllocateNothing) {
  VehicleStateListener listener(nullptr, "");
  const auto bytes = encode(message(10.0, vehicle_state_t::TURN_INDICATOR_BOTH, true, -0.1));
  test::AllocationScope scope;
  for (int i = 0; i < 100; ++i) {
    EXPECT_TRUE(listener.accept(bytes.data(), static_cast<int>(bytes.size()), i));
    EXPECT_TRUE(listener.latest());
  }
  EXPECT_EQ(scope.count(), 0u);
}

TEST(VehicleStateListener, AReaderRacingTheWriterNeverSeesATornState) {
  // Every message the writer stores is self-consistent (speed = k / 20, yaw rate =
  // -k / 1000: within the bounds; utime = k, indicator k % 4, received at k - 1): a torn read would mix two of them.
  // The writer cycles through them until the reader has read enough.
  VehicleStateListener listener(nullptr, "");
  constexpr int kMessages = 1000, kChanges = 2000;
  std::vector<std::vector<std::uint8_t>> messages;
  for (int k = 1; k <= kMessages; ++k) {
    vehicle_state_t m = message(k / 20.0, static_cast<std::int8_t>(k % 4), true, -k / 1000.0);
    m.utime = k;
    messages.push_back(encode(m));
  }
  std::atomic<bool> stop{false};
  std::atomic<std::uint64_t> written{0};
  std::thread writer([&] {
    for (std::size_t i = 0; !stop.load(std::memory_order_relaxed); ++i) {
      const auto& bytes = messages[i % messages.size()];
      listener.accept(bytes.data(), static_cast<int>(bytes.size()), static_cast<std::int64_t>(i % messages.size()));
      written.fetch_add(1, std::memory_order_relaxed);
    }
  });
  int torn = 0, changes = 0;
  long reads = 0;
  std::int64_t last = -1;
  while (written.load() == 0) std::this_thread::yield();
  while (changes < kChanges && reads < 100'000'000) {
    const auto s = listener.latest();
    if (!s) continue;
    ++reads;
    const auto k = s->utime;
    torn += s->speed_mps != static_cast<double>(k) / 20.0 || s->yaw_rate_radps != -static_cast<double>(k) / 1000.0 ||
            s->indicator != static_cast<TurnIndicator>(k % 4) || s->received_ns != k - 1;
    changes += k != last;
    last = k;
  }
  stop = true;
  writer.join();
  EXPECT_EQ(torn, 0) << "of " << reads << " reads";
  EXPECT_GE(changes, kChanges) << "the reader saw the writer's values change under it (" << written.load()
                               << " written)";
}

TEST(VehicleStateListener, AStaleStateGivesNoInputs) {
  VehicleState s;
  s.received_ns = 1'000'000'000;
  s.speed_mps = 25.0;
  s.yaw_rate_radps = 0.01;
  s.indicator = TurnIndicator::left;
  const VehicleInputs fresh = vehicle_inputs(s, 1'400'000'000, 500'000'000);
  EXPECT_EQ(fresh.speed_mps, 25.0);
  EXPECT_EQ(fresh.yaw_rate_radps, 0.01);
  EXPECT_EQ(fresh.indicator, TurnIndicator::left);
  const VehicleInputs stale = vehicle_inputs(s, 1'600'000'000, 500'000'000);
  EXPECT_FALSE(stale.speed_mps) << "the configured speed then";
  EXPECT_FALSE(stale.yaw_rate_radps);
  EXPECT_EQ(stale.indicator, TurnIndicator::none);
  EXPECT_FALSE(vehicle_inputs(std::nullopt, 0, 500'000'000).speed_mps);
}

}  // namespace
}  // namespace ccdlane
