// The vehicle state listener: messages published on an in-process bus (memq://) become
// the latest state; invalid ones are refused and counted; taking a message allocates
// nothing; a reader racing the writer never sees a torn state; a stale state gives no
// inputs.
#include "bus/vehicle_state_listener.hpp"

#include <atomic>
#include <thread>
#include <vector>

#include <ccdlane/vehicle_state_t.hpp>
#include <gtest/gtest.h>

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
  // Every message the writer stores is self-consistent (speed = k, yaw rate = -k,
  // utime = k, indicator k % 4, received at k - 1): a torn read would mix two of them.
  // The writer cycles through them until the reader has read enough.
  VehicleStateListener listener(nullptr, "");
  constexpr int kMessages = 1000, kChanges = 2000;
  std::vector<std::vector<std::uint8_t>> messages;
  for (int k = 1; k <= kMessages; ++k) {
    vehicle_state_t m = message(k, static_cast<std::int8_t>(k % 4), true, -k);
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
    torn += s->speed_mps != static_cast<double>(k) || s->yaw_rate_radps != -static_cast<double>(k) ||
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
