// Lane-line identities.
#include "core/lane/lane_tracker.hpp"

#include <algorithm>
#include <cmath>

namespace ccdlane {
namespace {
constexpr double kSameLineMm = 1000.0;  // an earlier line this near a seen one is that line
}

void LaneTracker::update(std::span<const RoadLine> lines, std::span<const int> prior_index, std::span<int> ids) {
  const std::size_t n = std::min({lines.size(), prior_index.size(), ids.size(), static_cast<std::size_t>(kCapacity)});
  std::array<bool, kCapacity> continued{};
  double shift = 0.0;  // how far the road moved sideways since the last frame (mean of the continued lines)
  int shifts = 0;
  for (std::size_t j = 0; j < n; ++j) {
    const int p = prior_index[j];
    if (p < 0 || p >= count_) continue;
    continued[static_cast<std::size_t>(p)] = true;
    shift += lines[j].y0_mm - lines_[static_cast<std::size_t>(p)].y0_mm;
    ++shifts;
  }
  if (shifts > 0) shift /= shifts;
  if (shifts == 0 && count_ == 0) next_id_ = 0;
  for (std::size_t j = 0; j < n; ++j) {
    const int p = prior_index[j];
    if (p >= 0 && p < count_) {
      ids[j] = ids_[static_cast<std::size_t>(p)];
      continue;
    }
    // Not continued by detection, but where an unclaimed earlier line should now be:
    // that line, found again.
    int found = -1;
    for (int k = 0; k < count_ && found < 0; ++k)
      if (!continued[static_cast<std::size_t>(k)] &&
          std::abs(lines_[static_cast<std::size_t>(k)].y0_mm + shift - lines[j].y0_mm) < kSameLineMm)
        found = k;
    if (found >= 0) {
      continued[static_cast<std::size_t>(found)] = true;
      ids[j] = ids_[static_cast<std::size_t>(found)];
    } else {
      ids[j] = next_id_++;
    }
  }

  // Next frame's priors: this frame's lines, then the ones still coasting (moved with
  // the road) unless a line seen now is already there.
  std::array<RoadLine, kCapacity> next_lines{};
  std::array<int, kCapacity> next_ids{}, next_missed{};
  int count = 0;
  for (std::size_t j = 0; j < n; ++j, ++count) {
    next_lines[static_cast<std::size_t>(count)] = lines[j];
    next_ids[static_cast<std::size_t>(count)] = ids[j];
    next_missed[static_cast<std::size_t>(count)] = 0;
  }
  for (int k = 0; k < count_ && count < kCapacity; ++k) {
    const auto kk = static_cast<std::size_t>(k);
    if (continued[kk] || missed_[kk] + 1 > kCoastFrames) continue;
    RoadLine moved = lines_[kk];
    moved.y0_mm += shift;
    bool taken = false;
    for (std::size_t j = 0; j < n; ++j) taken = taken || std::abs(lines[j].y0_mm - moved.y0_mm) < kSameLineMm;
    if (taken) continue;
    next_lines[static_cast<std::size_t>(count)] = moved;
    next_ids[static_cast<std::size_t>(count)] = ids_[kk];
    next_missed[static_cast<std::size_t>(count)] = missed_[kk] + 1;
    ++count;
  }
  lines_ = next_lines;
  ids_ = next_ids;
  missed_ = next_missed;
  count_ = count;
}

void LaneTracker::coast() {
  int kept = 0;
  for (int k = 0; k < count_; ++k) {
    if (++missed_[static_cast<std::size_t>(k)] > kCoastFrames) continue;
    lines_[static_cast<std::size_t>(kept)] = lines_[static_cast<std::size_t>(k)];
    ids_[static_cast<std::size_t>(kept)] = ids_[static_cast<std::size_t>(k)];
    missed_[static_cast<std::size_t>(kept)] = missed_[static_cast<std::size_t>(k)];
    ++kept;
  }
  count_ = kept;
}

void LaneTracker::rescale(double factor) {
  for (int k = 0; k < count_; ++k) {
    RoadLine& l = lines_[static_cast<std::size_t>(k)];
    l.y0_mm *= factor;
    l.c_per_mm /= factor;
  }
}

}  // namespace ccdlane
