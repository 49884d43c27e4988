// The road's vanishing point from the lane-mark candidates themselves: the row filter's
// bars (paint, raised markers, seams' lips, cars' trim) are points in the picture; those
// of one lane line lie on one straight line near the car, and the road's lines meet at
// one point. A Hough vote over the bars' centres finds the straight lines they make
// (their positions are sub-pixel and a line spans hundreds of rows, so its direction is
// known to a fraction of a degree), and the point most of the lines' weight passes
// through is the vanishing point.
//
// This is the edge vote's (vanishing_point.hpp) sharper companion: that one lets every
// edge pixel vote along its own 3x3 gradient direction, which a degree or two of noise
// per edge and the strong edges of cars and shadows pull off the lane lines' crossing by
// 20 to 50 pixels on concrete freeways; here only bars vote, and only where many of them
// line up.
#pragma once

#include <array>
#include <span>
#include <vector>

#include "core/detection/lane_marks.hpp"
#include "core/detection/vanishing_point.hpp"
#include "core/geometry/camera_model.hpp"

namespace ccdlane {

// A straight line of bars in ideal pixel coordinates: x = x_bottom + slope (y - y_bottom).
struct BarLine {
  double x_bottom = 0.0;  // where it crosses the picture's bottom row
  double slope = 0.0;     // dx/dy
  double weight = 0.0;    // the bars on it (each by its contrast, capped)
  int bars = 0;
  double y_top = 0.0, y_bottom = 0.0;  // the rows its bars span
};

class VanishingLineFinder {
 public:
  // Sizes every buffer for frames of camera.Nu x camera.Nv and up to max_bars bars;
  // nothing else allocates.
  VanishingLineFinder(const CameraSpec& camera, int max_bars, const VanishingPointSearch& search = {});

  // Forgets the bars added; then add() the bars of one or more scans (their px, py:
  // observed 1-based pixels; beyond max_bars they are left out). A bar weighs by its
  // contrast in units of its light: `row_shares[scan_row]` is the share of daylight's
  // contrast threshold its scan row had (LaneDetector::row_threshold_shares; none: 1).
  void clear() { n_ = 0; }
  void add(std::span<const MarkCandidate> bars, std::span<const float> row_shares = {});
  // The vanishing point of the straight lines the bars added make, for a camera mounted
  // near `nominal` (yaw and pitch within the search's bounds). The result stays valid
  // until the next call; `lines()` are the lines it was found from.
  const VanishingPoint& find(const CameraPose& nominal);
  std::span<const BarLine> lines() const { return {lines_.data(), static_cast<std::size_t>(num_lines_)}; }

  static constexpr int kMaxLines = 12;
  static constexpr int kAngleBins = 300;  // the vote's directions, 75 degrees either side of the vertical
  // A line of bars needs this many, over this many rows: a dashed line gives a few per
  // dash on every second or third row near the car, a row of raised markers one or two
  // per marker.
  static constexpr int kMinBars = 6;
  static constexpr double kMinRowSpan = 40.0;
  // The point needs lines from both sides of it (leaning left and right), whose weights'
  // geometric mean is at least this many bars.
  static constexpr double kMinSideWeight = 6.0;

 private:
  void vote(int delta_sign);
  int strongest(int& bi, int& bj) const;
  bool fit_line(int bi, int bj, BarLine& out);
  void choose_point(const VanishingPoint& region);
  double across(const BarLine& l, double x, double y) const;  // distance from l, pixels
  bool below(const BarLine& l, double y) const;               // l's bars run below row y, most of them
  std::size_t row_of(int i) const;                            // bar i's picture row
  double chance_bars(double x_bottom, double slope, double top, double bottom) const;

  CameraSpec camera_;
  VanishingPointSearch search_;
  std::vector<double> ix_, iy_;    // the bars' ideal pixel centres
  std::vector<float> contrast_w_;  // their weights by contrast (add)
  std::vector<float> w_;           // and shared with their rows' other bars (find: from all bars added so far)
  std::vector<char> used_;         // on a line found
  std::vector<int> row_bars_;      // bars per picture row
  int n_ = 0;
  std::vector<float> votes_;  // kAngleBins x x_bins_ (rho)
  std::array<double, kAngleBins> cos_{}, sin_{};
  int x_bins_ = 0;
  double x_lo_ = 0.0, y_bottom_ = 0.0;
  double angle_px_ = 1.0;  // the camera's focal length in pixels over the reference's (find)
  std::array<BarLine, kMaxLines> lines_{};
  int num_lines_ = 0;
  VanishingPoint result_;
};

}  // namespace ccdlane
