// Which of a search's starting poses' lanes the search takes (lane_estimator_search.cpp):
// the best ranked lane, else the first of each weaker kind, of the poses whose solves
// were not lone ones.
#pragma once

#include <algorithm>
#include <cstdint>
#include <optional>
#include <span>

#include "core/lane/searched_lanes.hpp"
#include "core/lane/solved_attitudes.hpp"

namespace ccdlane {

// What a starting pose's solve was to the search: a lane at the height it was looked from,
// one of a lane's width only at another height, one with a line inside it, one with a line
// found only in the picture (the weaker kinds, in that order), or none.
enum class SearchedKind : std::uint8_t { none, lane, other_height, line_inside, from_picture };

// The poses taken for each kind; -1: none of it.
struct SearchChoice {
  int lane = -1;          // the best ranked lane (ranks_above)
  int other_height = -1;  // the first of each weaker kind
  int line_inside = -1;
  int from_picture = -1;
  bool lone_left_out = false;  // the lone solves' poses were left out (there was another)
  bool any() const { return lane >= 0 || other_height >= 0 || line_inside >= 0 || from_picture >= 0; }
};

// Of poses 0..count-1 (`kinds[p]`, and `ranks[p]` for each lane), those a lone solve did
// not give (SolvedAttitudes::lone: a hollow of clutter one or two starting poses fell
// into, where most of the search's solves reached another attitude), if any pose of any
// kind is left; else all of them.
template <int kMaxPoses>
SearchChoice choose_searched(std::span<const SearchedKind> kinds, std::span<const std::optional<LaneRank>> ranks,
                             const SolvedAttitudes<kMaxPoses>& attitudes, int count) {
  for (const bool lone_too : {false, true}) {
    SearchChoice c;
    c.lone_left_out = !lone_too;
    const auto taken = [&](int p, SearchedKind what) {
      return kinds[static_cast<std::size_t>(p)] == what && (lone_too || !attitudes.lone(p));
    };
    std::optional<LaneRank> lane_rank;
    int lane_picks = 0;  // the most own-lane picks of a lane taken
    for (int p = 0; p < count; ++p) {
      const std::optional<LaneRank>& rank = ranks[static_cast<std::size_t>(p)];
      if (taken(p, SearchedKind::lane) && rank && ranks_above(*rank, lane_rank, lane_picks)) {
        lane_picks = std::max(rank->own_picks, lane_picks);
        lane_rank = rank;
        c.lane = p;
      }
      if (taken(p, SearchedKind::other_height) && c.other_height < 0) c.other_height = p;
      if (taken(p, SearchedKind::line_inside) && c.line_inside < 0) c.line_inside = p;
      if (taken(p, SearchedKind::from_picture) && c.from_picture < 0) c.from_picture = p;
    }
    if (c.any()) return c;
  }
  return {};
}

}  // namespace ccdlane
