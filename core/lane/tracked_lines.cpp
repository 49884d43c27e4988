// Ids first, then order: the tracker matches lines in the solve's order, the estimate
// reports them left to right.
#include "core/lane/tracked_lines.hpp"

#include <cmath>
#include <span>
#include <utility>

#include "core/lane/lane_support.hpp"

namespace ccdlane {
namespace {

// Share of a line's picks it takes to be fully trusted (marks / (marks + this)).
constexpr double kConfidenceMarks = 10.0;

// The solve's line indices left to right: largest y0 first (insertion sort, n <= 4).
std::array<int, kMaxLaneLines> left_to_right(const SolveResult& r, int n) {
  std::array<int, kMaxLaneLines> order{};
  for (int j = 0; j < n; ++j) order[j] = j;
  for (int i = 1; i < n; ++i)
    for (int k = i; k > 0 && r.lines[order[k]].y0_mm > r.lines[order[k - 1]].y0_mm; --k)
      std::swap(order[k], order[k - 1]);
  return order;
}

}  // namespace

TrackedLines track_lines(LaneTracker& tracker, const SolveResult& r, const LaneFit& fit, double mount_psi_deg,
                         double departure_mm) {
  // Per line: its picks and their fit.
  std::array<int, kMaxLaneLines> marks{};
  std::array<double, kMaxLaneLines> sum2{};
  const std::span<const Pick> picks = fit.picks();
  const std::span<const double> residual_px = fit.residual_px();
  for (std::size_t i = 0; i < picks.size(); ++i) {
    const auto j = static_cast<std::size_t>(picks[i].line);
    ++marks[j];
    sum2[j] += residual_px[i] * residual_px[i];
  }
  TrackedLines t;
  const int n = std::min(r.num_lines, fit.num_lines());
  std::array<int, kMaxLaneLines> ids{};
  tracker.update({r.lines.data(), static_cast<std::size_t>(n)}, fit.prior_index().first(static_cast<std::size_t>(n)),
                 {ids.data(), static_cast<std::size_t>(n)});
  const std::array<int, kMaxLaneLines> order = left_to_right(r, n);
  t.num_lines = n;
  for (int k = 0; k < n; ++k) {
    const auto j = static_cast<std::size_t>(order[k]);
    const RoadLine& l = r.lines[j];
    EstimatedLine& out = t.lines[k];
    t.solve_line[k] = order[k];
    out.id = ids[j];
    out.y0_mm = l.y0_mm;
    out.m = l.m;
    out.c_per_mm = l.c_per_mm;
    out.marks = marks[j];
    // More picks, more trust; a line whose picks miss their marks, less.
    const double line_rms = marks[j] > 0 ? std::sqrt(sum2[j] / marks[j]) : 0.0;
    out.confidence = marks[j] / (marks[j] + kConfidenceMarks) / (1.0 + line_rms * line_rms);
    out.sigma_y0_mm = r.sigma.y0_mm[j];
    const LineSupport seen = line_support(picks, r.points_mm, order[k]);
    out.near_mm = seen.near_mm;
    out.far_mm = seen.far_mm;
  }
  const LaneMetrics& m = t.metrics = lane_metrics({t.lines.data(), static_cast<std::size_t>(n)},
                                                  rad_to_deg(r.pose.attitude.psi), mount_psi_deg, departure_mm);
  if (m.left >= 0) t.own.left = order[m.left];
  if (m.right >= 0) t.own.right = order[m.right];
  t.own.lane_width_mm = m.lane_width_mm;
  t.own.heading_deg = m.heading_deg;
  t.own.curvature_per_m = m.curvature_per_m;
  return t;
}

}  // namespace ccdlane
