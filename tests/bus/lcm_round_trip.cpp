// The round trip: LaneEstimate -> LcmPublisher -> bus -> subscriber -> LaneEstimate.
#include "tests/bus/lcm_round_trip.hpp"

#include <algorithm>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "bus/lane_message.hpp"
#include "daemon/allocation_counter.hpp"

namespace ccdlane::test {
namespace {

// Plain functions with a context, not subscribe(&Class::method): GCC 12's UBSan reports
// a false "invalid vptr" in LCM's member-function callback.
struct Received {
  std::vector<lane_estimate_t> lanes;
  std::vector<status_t> statuses;
  std::vector<std::string> channels;
};

void on_lane(const lcm::ReceiveBuffer*, const std::string& channel, const lane_estimate_t* m, Received* got) {
  got->channels.push_back(channel);
  got->lanes.push_back(*m);
}

void on_status(const lcm::ReceiveBuffer*, const std::string& channel, const status_t* m, Received* got) {
  got->channels.push_back(channel);
  got->statuses.push_back(*m);
}

LaneEstimate estimate_for(std::uint64_t frame) {
  LaneEstimate e;
  e.frame = frame;
  e.t_ns = static_cast<std::int64_t>(frame) * 33'333'333;
  e.ok = frame % 3 != 0;
  e.reason = e.ok ? EstimateFailure::none : EstimateFailure::no_lane;
  e.psi_deg = 0.01 * static_cast<double>(frame);
  e.num_lines = 2;
  e.lines[0].y0_mm = 1750.0;
  e.lines[1].y0_mm = -1750.0 + static_cast<double>(frame);
  e.departure = Departure::left;
  e.latency_us = 100 + static_cast<std::int64_t>(frame);
  return e;
}

}  // namespace

void lcm_round_trip(LcmPublisher& publisher, lcm::LCM& subscriber) {
  Received got;
  lcm::Subscription* lanes = subscriber.subscribeFunction(publisher.lanes_channel(), &on_lane, &got);
  lcm::Subscription* statuses = subscriber.subscribeFunction(publisher.status_channel(), &on_status, &got);

  constexpr int kFrames = 20;
  // Warm up once: LCM computes type hashes and sets up its send path on first use.
  ASSERT_TRUE(publisher.publish_lane(estimate_for(0), 1, 2));
  status_t status{};
  status.camera.reserve(kStatusTextMax);
  status.camera = "test camera";
  status.frames_in_total = 42;
  ASSERT_TRUE(publisher.publish_status(status));

  allocation_counter::start_counting();
  for (int i = 1; i < kFrames; ++i)
    ASSERT_TRUE(publisher.publish_lane(estimate_for(static_cast<std::uint64_t>(i)), 1000 + i, 2000 + i));
  status.frames_in_total = 43;
  ASSERT_TRUE(publisher.publish_status(status));
  const std::uint64_t allocations = allocation_counter::count();
  allocation_counter::stop_counting();
  EXPECT_EQ(allocations, 0u) << "publishing must not use operator new";

  while (static_cast<int>(got.lanes.size()) < kFrames || got.statuses.size() < 2) {
    if (subscriber.handleTimeout(2000) <= 0) break;
  }
  ASSERT_EQ(got.lanes.size(), static_cast<std::size_t>(kFrames));
  EXPECT_EQ(got.channels.front(), publisher.lanes_channel());
  EXPECT_EQ(std::count(got.channels.begin(), got.channels.end(), publisher.status_channel()), 2);
  for (int i = 0; i < kFrames; ++i) {
    const LaneEstimate back = from_message(got.lanes[static_cast<std::size_t>(i)]);
    const LaneEstimate sent = estimate_for(static_cast<std::uint64_t>(i));
    EXPECT_EQ(back.frame, sent.frame);
    EXPECT_EQ(back.ok, sent.ok);
    EXPECT_EQ(back.reason, sent.reason);
    EXPECT_EQ(back.psi_deg, sent.psi_deg);
    EXPECT_EQ(back.lines[1].y0_mm, sent.lines[1].y0_mm);
    EXPECT_EQ(back.departure, Departure::left);
    if (i > 0) {
      EXPECT_EQ(got.lanes[static_cast<std::size_t>(i)].publish_utime, 2000 + i);
    }
  }
  subscriber.unsubscribe(lanes);
  subscriber.unsubscribe(statuses);
  ASSERT_EQ(got.statuses.size(), 2u);
  EXPECT_EQ(got.statuses[1].frames_in_total, 43);
  EXPECT_EQ(got.statuses[1].camera, "test camera");
}

}  // namespace ccdlane::test
