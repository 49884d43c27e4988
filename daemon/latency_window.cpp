// Percentiles by selection (nth_element), not sorting: linear time, in place.
#include "daemon/latency_window.hpp"

#include <algorithm>
#include <cmath>

namespace ccdlane {

LatencyWindow::LatencyWindow(std::size_t capacity)
    : capacity_(capacity == 0 ? 1 : capacity), samples_(std::make_unique<std::int64_t[]>(capacity_)) {}

void LatencyWindow::add(std::int64_t latency_us) noexcept {
  if (count_ == 0 || latency_us > max_) max_ = latency_us;
  ++count_;
  if (stored_ < capacity_) samples_[stored_++] = latency_us;
}

// Nearest rank: the smallest sample with at least `fraction` of the samples at or below it.
std::int64_t LatencyWindow::percentile(double fraction) noexcept {
  const auto rank = static_cast<std::size_t>(std::ceil(fraction * static_cast<double>(stored_)));
  const std::size_t index = rank == 0 ? 0 : rank - 1;
  std::int64_t* first = samples_.get();
  std::nth_element(first, first + index, first + stored_);
  return first[index];
}

LatencySummary LatencyWindow::take() noexcept {
  LatencySummary s;
  s.samples = count_;
  if (stored_ > 0) {
    s.p50_us = percentile(0.50);
    s.p99_us = percentile(0.99);
    s.max_us = max_;
  }
  stored_ = 0;
  count_ = 0;
  max_ = 0;
  return s;
}

}  // namespace ccdlane
