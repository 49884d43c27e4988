// The median of a set of values, in place and allocation-free (selection, not a sort):
// the per-frame path takes it of its scratch buffers.
#pragma once

#include <algorithm>
#include <cstddef>
#include <limits>
#include <span>

namespace ccdlane {

// The median of v, reordering v: the middle value, the mean of the middle two for an even
// count, NaN for none.
inline double median_in_place(std::span<double> v) {
  if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  if (v.size() % 2) return *mid;
  return 0.5 * (*mid + *std::max_element(v.begin(), mid));
}

}  // namespace ccdlane
