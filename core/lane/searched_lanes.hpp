// The lanes a search's starting poses gave: how the search ranks them (ranks_above), and
// each by its own lines and the height it was solved at, to tell a lane from two lanes
// taken for one (spans_two_lanes).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>

#include "core/lane/lane_support.hpp"

namespace ccdlane {

// What the search ranks a starting pose's lane by (lane_estimator_search.cpp): the picks
// on its own lane's lines, the lines its solve holds, and its picks' rms.
struct LaneRank {
  int own_picks = 0;
  int lines = 0;
  double rms_px = 0.0;
};

// Whether `lane` ranks above `taken`, the lane the search holds so far (none: it does),
// where `most_own_picks` is the most own-lane picks any lane had so far.
// More own-lane picks than that by more than a count's own spread (its Poisson sigma)
// rank above. Within the spread the count says nothing. Then the lane whose solve holds
// more of the road's lines ranks above: a pose a degree off finds the own lane's lines,
// which are near and many-marked, but not the next lanes' rows of specks 15-40 m away,
// which only a pose close to the camera's puts where they are (the fourteen further mount
// rows of the development set: lines found 3779 -> 3842 of 4872, own lines 2327 both).
// With as many lines, the lane whose picks fit better ranks above, when better by more
// than an rms's own spread over that many picks, 1 / sqrt(2 n) of it (a curved Udacity
// picture's lane from the vanishing point's pose pitched 2 degrees fitted its 95 picks to
// 0.27 px against 0.28, 6 px off the far dash).
inline bool ranks_above(const LaneRank& lane, const std::optional<LaneRank>& taken, int most_own_picks) {
  if (!taken) return true;
  const double spread = std::sqrt(static_cast<double>(most_own_picks));
  if (lane.own_picks > most_own_picks + spread) return true;
  if (lane.own_picks < most_own_picks - spread) return false;
  if (lane.lines != taken->lines) return lane.lines > taken->lines;
  const double rms_spread = taken->rms_px / std::sqrt(2.0 * std::max(1, most_own_picks));
  return lane.rms_px < taken->rms_px - rms_spread;
}

template <int kMaxPoses>
class SearchedLanes {
 public:
  // Pose `pose`'s solve was a lane of a lane's width: at the height it was looked from
  // (`as_looked_from`), or only at another.
  void add(int pose, const OwnLanePlace& place, bool as_looked_from) {
    if (pose < 0 || pose >= kMaxPoses) return;
    lanes_[static_cast<std::size_t>(pose)] = Lane{place, as_looked_from};
    end_ = std::max(end_, pose + 1);
  }
  // Pose `pose`'s lane is no evidence of anything after all.
  void remove(int pose) {
    if (pose >= 0 && pose < kMaxPoses) lanes_[static_cast<std::size_t>(pose)].reset();
  }
  bool as_looked_from(int pose) const { return lane(pose) && lane(pose)->as_looked_from; }

  // Whether another pose's lane shows pose `chosen`'s to be two lanes.
  bool two_lanes(int chosen) const {
    for (int j = 0; j < end_; ++j)
      if (shows_two_lanes(chosen, j)) return true;
    return false;
  }
  // The first pose whose lane shows pose `chosen`'s to be two lanes and that no other
  // pose's lane shows to be two lanes itself; -1: none.
  int narrower_than(int chosen) const {
    for (int j = 0; j < end_; ++j)
      if (shows_two_lanes(chosen, j) && !two_lanes(j)) return j;
    return -1;
  }

 private:
  struct Lane {
    OwnLanePlace place;
    bool as_looked_from = false;
  };
  const std::optional<Lane>& lane(int pose) const {
    static const std::optional<Lane> none;
    return pose >= 0 && pose < kMaxPoses ? lanes_[static_cast<std::size_t>(pose)] : none;
  }
  bool shows_two_lanes(int wide, int narrow) const {
    return wide != narrow && lane(wide) && lane(narrow) && spans_two_lanes(lane(wide)->place, lane(narrow)->place);
  }

  std::array<std::optional<Lane>, kMaxPoses> lanes_{};
  int end_ = 0;  // one past the last pose added
};

}  // namespace ccdlane
