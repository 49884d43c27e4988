#include "core/lane/search_choice.hpp"

#include <array>

#include <gtest/gtest.h>

namespace ccdlane {
namespace {

constexpr int kPoses = 8;

struct Search {
  std::array<SearchedKind, kPoses> kinds{};
  std::array<std::optional<LaneRank>, kPoses> ranks{};
  SolvedAttitudes<kPoses> attitudes;
  // Pose p solved to this pitch and yaw (degrees) and was to the search `kind`.
  void pose(int p, double theta_deg, double psi_deg, SearchedKind kind, int own_picks = 0) {
    attitudes.add(p, deg_to_rad(theta_deg), deg_to_rad(psi_deg));
    kinds[static_cast<std::size_t>(p)] = kind;
    if (kind == SearchedKind::lane) ranks[static_cast<std::size_t>(p)] = LaneRank{own_picks, 2, 0.5};
  }
  SearchChoice choose(int count = kPoses) const { return choose_searched<kPoses>(kinds, ranks, attitudes, count); }
};

// TuSimple still 40 at light x0.97: the one lane at the height looked from was a lone
// solve's (the camera looking up), while the poses that solved to the camera's attitude
// gave lanes only of another height. The lane of another height is taken, and the lone
// lane is left out.
TEST(SearchChoice, ALoneSolvesLaneYieldsToAWeakerKindThatMostPosesReach) {
  Search s;
  for (int p = 0; p < 6; ++p) s.pose(p, 7.0, 1.4, p == 2 ? SearchedKind::other_height : SearchedKind::none);
  s.pose(6, -5.6, -13.1, SearchedKind::lane, 91);
  const SearchChoice c = s.choose();
  EXPECT_EQ(c.lane, -1);
  EXPECT_EQ(c.other_height, 2);
  EXPECT_TRUE(c.lone_left_out);
}

// Where every pose that gave a lane of any kind is lone, the search takes them as it did
// without the rule: a lane is better than none.
TEST(SearchChoice, WhereEveryLaneIsALoneSolvesTheyAreTakenAsBefore) {
  Search s;
  for (int p = 0; p < 6; ++p) s.pose(p, 7.0, 1.4, SearchedKind::none);
  s.pose(6, -5.6, -13.1, SearchedKind::lane, 91);
  s.pose(7, 12.0, 3.0, SearchedKind::line_inside);
  const SearchChoice c = s.choose();
  EXPECT_EQ(c.lane, 6);
  EXPECT_EQ(c.line_inside, 7);
  EXPECT_FALSE(c.lone_left_out);
}

// Among the lanes most poses reach, the ranking is ranks_above's (the most own-lane
// picks beyond a count's spread), and each weaker kind's first pose is kept beside it.
TEST(SearchChoice, AmongSharedSolvesTheLanesRankAsRanksAboveSays) {
  Search s;
  s.pose(0, 7.0, 1.4, SearchedKind::line_inside);
  s.pose(1, 7.1, 1.3, SearchedKind::lane, 100);
  s.pose(2, 7.0, 1.5, SearchedKind::lane, 130);
  s.pose(3, 6.9, 1.4, SearchedKind::lane, 128);
  s.pose(4, 7.2, 1.4, SearchedKind::from_picture);
  const SearchChoice c = s.choose(5);
  EXPECT_EQ(c.lane, 2);
  EXPECT_EQ(c.line_inside, 0);
  EXPECT_EQ(c.from_picture, 4);
  EXPECT_EQ(c.other_height, -1);
  EXPECT_TRUE(c.lone_left_out);
}

}  // namespace
}  // namespace ccdlane
