// Percentiles against a sorted copy; the window keeps counting beyond its capacity.
#include "daemon/latency_window.hpp"

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "daemon/allocation_counter.hpp"

namespace ccdlane {
namespace {

std::int64_t nearest_rank(std::vector<std::int64_t> v, double p) {
  std::sort(v.begin(), v.end());
  const auto rank = static_cast<std::size_t>(std::ceil(p * static_cast<double>(v.size())));
  return v[rank == 0 ? 0 : rank - 1];
}

TEST(LatencyWindow, PercentilesAreNearestRankOfTheSamples) {
  std::mt19937 rng(7);
  std::lognormal_distribution<double> latency(6.0, 0.8);  // ~400 us with a long tail
  LatencyWindow window(4096);
  for (int round = 0; round < 5; ++round) {
    std::vector<std::int64_t> samples(100 + 937 * static_cast<std::size_t>(round));
    for (auto& s : samples) s = static_cast<std::int64_t>(latency(rng));
    for (auto s : samples) window.add(s);
    const LatencySummary sum = window.take();
    EXPECT_EQ(sum.samples, static_cast<std::int64_t>(samples.size()));
    EXPECT_EQ(sum.p50_us, nearest_rank(samples, 0.50));
    EXPECT_EQ(sum.p99_us, nearest_rank(samples, 0.99));
    EXPECT_EQ(sum.max_us, *std::max_element(samples.begin(), samples.end()));
  }
}

TEST(LatencyWindow, SmallWindowsAndEmptyOnes) {
  LatencyWindow window(16);
  EXPECT_EQ(window.take().samples, 0);
  window.add(5);
  LatencySummary one = window.take();
  EXPECT_EQ(one.p50_us, 5);
  EXPECT_EQ(one.p99_us, 5);
  EXPECT_EQ(one.max_us, 5);
  for (int i = 1; i <= 16; ++i) window.add(i);
  const LatencySummary s = window.take();
  EXPECT_EQ(s.p50_us, 8);   // 16 samples 1..16: rank ceil(8) = 8
  EXPECT_EQ(s.p99_us, 16);  // rank ceil(15.84) = 16
  const LatencySummary empty = window.take();
  EXPECT_EQ(empty.samples, 0);
  EXPECT_EQ(empty.max_us, 0);
}

TEST(LatencyWindow, BeyondCapacitySamplesCountAndRaiseTheMaximum) {
  LatencyWindow window(10);
  for (int i = 0; i < 10; ++i) window.add(100);
  window.add(5000);  // not stored, still the maximum
  const LatencySummary s = window.take();
  EXPECT_EQ(s.samples, 11);
  EXPECT_EQ(s.p99_us, 100);
  EXPECT_EQ(s.max_us, 5000);
}

TEST(LatencyWindow, AddingAndSummarisingDoNotAllocate) {
  LatencyWindow window(1000);
  allocation_counter::start_counting();
  for (int i = 0; i < 2000; ++i) window.add(i % 777);
  (void)window.take();
  EXPECT_EQ(allocation_counter::count(), 0u);
  allocation_counter::stop_counting();
}

}  // namespace
}  // namespace ccdlane
