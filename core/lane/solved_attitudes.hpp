// Where a search's starting poses' solves converged: the camera's attitude is one, and
// the search's poses surround it, so most of them that solve at all lead there; a fit of
// clutter is a hollow that one or two starting poses fall into.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>

#include "core/geometry/types.hpp"

namespace ccdlane {

// Solves this close in pitch and in yaw reached the same attitude. The poses that lead to
// a still's lane solve within a tenth or two of a degree of each other (TuSimple's
// development stills: 6.94-7.06 degrees of pitch from a dozen poses); a lane of clutter
// lies degrees away (still 40 at light x0.97: pitch -5.6, yaw -13 degrees, from two
// poses, where twenty solved at 7.0 and 1.4). At 0.5 degree the development set read the
// same; at 2, as without the rule (docs/real-roads.md).
inline constexpr double kSameAttitudeDeg = 1.0;

template <int kMaxPoses>
class SolvedAttitudes {
 public:
  // Pose `pose`'s solve converged to this pitch and yaw (radians).
  void add(int pose, double theta_rad, double psi_rad) {
    if (pose < 0 || pose >= kMaxPoses) return;
    solved_[static_cast<std::size_t>(pose)] = Solved{theta_rad, psi_rad};
    end_ = std::max(end_, pose + 1);
    most_ = -1;
  }

  // How many solves reached pose `pose`'s attitude, its own included; 0 when it did not
  // solve.
  int sharing(int pose) const {
    if (pose < 0 || pose >= end_ || !solved_[static_cast<std::size_t>(pose)]) return 0;
    const Solved& at = *solved_[static_cast<std::size_t>(pose)];
    int n = 0;
    for (int j = 0; j < end_; ++j)
      n += solved_[static_cast<std::size_t>(j)] && same(at, *solved_[static_cast<std::size_t>(j)]);
    return n;
  }

  // Whether pose `pose`'s solve is a lone one: another attitude was reached from more
  // than twice as many poses. Two solves against four is not (the development stills'
  // own lanes were reached from as few as 2 of 4, 3 of 4, 4 of 6); the lanes of clutter
  // seen were reached from 1 of 4, 2 of 20, 1 of 17, 3 of 16.
  bool lone(int pose) const {
    const int n = sharing(pose);
    if (n == 0) return false;
    if (most_ < 0)  // once for all the poses the search asks about
      for (int j = 0; j < end_; ++j) most_ = std::max(most_, sharing(j));
    return 2 * n < most_;
  }

 private:
  struct Solved {
    double theta, psi;
  };
  static bool same(const Solved& a, const Solved& b) {
    const double within = deg_to_rad(kSameAttitudeDeg);
    return std::abs(a.theta - b.theta) <= within && std::abs(a.psi - b.psi) <= within;
  }

  std::array<std::optional<Solved>, kMaxPoses> solved_{};
  int end_ = 0;            // one past the last pose added
  mutable int most_ = -1;  // the most solves one attitude was reached from; -1: not counted since the last add
};

}  // namespace ccdlane
