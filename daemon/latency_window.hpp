// Capture-to-publish latency over one status period: p50, p99 and max from a fixed
// sample buffer, without allocating after construction.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>

namespace ccdlane {

struct LatencySummary {
  std::int64_t samples = 0;  // all samples of the window, also those beyond capacity
  std::int64_t p50_us = 0;   // nearest-rank percentiles of the stored samples; 0 when none
  std::int64_t p99_us = 0;
  std::int64_t max_us = 0;  // over all samples
};

class LatencyWindow {
 public:
  explicit LatencyWindow(std::size_t capacity);  // the only allocation

  // Beyond capacity a sample still counts and raises max, but is not ranked.
  void add(std::int64_t latency_us) noexcept;
  // Summarises the window (reorders the stored samples) and starts the next.
  LatencySummary take() noexcept;

  std::size_t capacity() const { return capacity_; }

 private:
  std::int64_t percentile(double fraction) noexcept;

  std::size_t capacity_;
  std::unique_ptr<std::int64_t[]> samples_;
  std::size_t stored_ = 0;
  std::int64_t count_ = 0;
  std::int64_t max_ = 0;
};

}  // namespace ccdlane
