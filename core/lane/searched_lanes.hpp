// The lanes a search's starting poses gave, each by its own lines and the height it was
// solved at, to tell a lane from two lanes taken for one (spans_two_lanes).
#pragma once

#include <algorithm>
#include <array>
#include <optional>

#include "core/lane/lane_support.hpp"

namespace ccdlane {

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
