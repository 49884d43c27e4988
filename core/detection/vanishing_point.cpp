// Vanishing point from the picture: the paint measure's Sobel gradient on every second
// pixel of every second row below the highest horizon the mount allows; each edge along
// the road votes along its (undistorted) direction into an accumulator over the search
// region; the strongest 3x3 neighbourhood, refined to its centroid, is the point.
#include "core/detection/vanishing_point.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "core/detection/ground_projector.hpp"
#include "core/detection/paint_measure.hpp"

namespace ccdlane {
namespace {

// Edges within this angle of the horizontal run across the road (shadows, bumpers, the
// far ends of dashes): they say nothing of where the road goes.
constexpr double kMinEdgeSlant = 0.26;  // sin(15 degrees)
// An edge votes only for points at least this far above it (pixels): just above itself
// its direction is no better than its gradient's noise.
constexpr double kMinRise = 24.0;
constexpr double kVertical = 0.07;      // |dx/dy| of an edge within 4 degrees of the vertical
constexpr int kStep = 2;                // every second row and column
constexpr double kMaxWeight = 3.0;      // one strong edge (a car's) counts as three faint ones
constexpr double kMaxRegionPx = 800.0;  // bins are widened so that the region fits in ~200 x 200

}  // namespace

VanishingPointFinder::VanishingPointFinder(const CameraSpec& camera, const DetectionConfig& config,
                                           const VanishingPointSearch& search)
    : camera_(camera), config_(config), search_(search) {
  for (auto& r : rows_) r.resize(static_cast<std::size_t>(camera.Nu));
  bin_px_ = std::max(2.0, 4.0 * camera.Nu / 1280.0);
  const int max_bins = static_cast<int>(std::ceil(kMaxRegionPx / bin_px_)) + 2;
  votes_.resize(static_cast<std::size_t>(max_bins) * max_bins);
  votes_right_.resize(votes_.size());
}

void set_search_region(const CameraSpec& camera, const CameraPose& nominal, const VanishingPointSearch& search,
                       VanishingPoint& r) {
  // Where the road's direction may appear: the yaw and pitch bounds' corners.
  r.x_lo = r.y_lo = 1e300;
  r.x_hi = r.y_hi = -1e300;
  for (const double dpsi : {-search.max_yaw_error_deg, 0.0, search.max_yaw_error_deg})
    for (const double dtheta : {-search.max_pitch_error_deg, 0.0, search.max_pitch_error_deg}) {
      CameraPose p = nominal;
      p.attitude.psi += deg_to_rad(dpsi);
      p.attitude.theta += deg_to_rad(dtheta);
      double x = 0, y = 0;
      if (!GroundProjector(camera, p).vanishing_point(0.0, x, y)) continue;
      r.x_lo = std::min(r.x_lo, x), r.x_hi = std::max(r.x_hi, x), r.y_lo = std::min(r.y_lo, y),
      r.y_hi = std::max(r.y_hi, y);
    }
}

void VanishingPointFinder::set_region(const CameraPose& nominal) {
  VanishingPoint& r = result_;
  set_search_region(camera_, nominal, search_, r);
  const int max_bins = static_cast<int>(std::ceil(kMaxRegionPx / bin_px_)) + 2;
  const double span = std::max(r.x_hi - r.x_lo, r.y_hi - r.y_lo);
  const double bin = std::max(bin_px_, span / (max_bins - 2));
  bins_x_ = std::clamp(static_cast<int>(std::ceil((r.x_hi - r.x_lo) / bin)), 1, max_bins);
  bins_y_ = std::clamp(static_cast<int>(std::ceil((r.y_hi - r.y_lo) / bin)), 1, max_bins);
  bin_px_ = bin;
}

void VanishingPointFinder::vote_row(const ImageView& image, int y) {
  // Rows y-1, y, y+1 of the measure are in rows_[0..2].
  const std::uint16_t *r0 = rows_[0].data(), *r1 = rows_[1].data(), *r2 = rows_[2].data();
  const double threshold = 4.0 * config_.min_contrast * static_cast<double>(paint_measure_levels_per_grey(image));
  const double py = y + 1.0;
  for (int x = 1 + (y / kStep) % kStep; x + 1 < image.width; x += kStep) {
    const double gx = (r0[x + 1] - r0[x - 1]) + 2.0 * (r1[x + 1] - r1[x - 1]) + (r2[x + 1] - r2[x - 1]);
    const double gy = (r2[x - 1] + 2.0 * r2[x] + r2[x + 1]) - (r0[x - 1] + 2.0 * r0[x] + r0[x + 1]);
    const double g = std::hypot(gx, gy);
    if (g < threshold) continue;
    // The edge's direction, and two points along it, undistorted: the division model of
    // distortion.hpp written out, as GroundProjector does, because this loop also runs
    // in unoptimised (sanitizer) builds, where Eigen's Vec2 costs ten times as much.
    const double tx = -gy / g, ty = gx / g;
    if (std::abs(ty) < kMinEdgeSlant) continue;
    auto ideal = [&](double px, double qy, double& ix, double& iy) {
      const double dx = px - camera_.cx, dy = qy - camera_.cy;
      const double den = 1.0 + camera_.k_px2 * (dx * dx + dy * dy);
      const double s = den > 0.0 ? 1.0 / den : 1.0;
      ix = camera_.cx + dx * s;
      iy = camera_.cy + dy * s;
    };
    double ax = 0, ay = 0, bx = 0, by = 0;
    ideal(x + 1.0, py, ax, ay);
    ideal(x + 1.0 + 8.0 * tx, py + 8.0 * ty, bx, by);
    if (std::abs(by - ay) < 1e-9) continue;
    const double slope = (bx - ax) / (by - ay);  // dx/dy of the edge's line
    const float w = static_cast<float>(std::min(g / threshold, kMaxWeight));
    // Lines left of the point lean one way, lines right of it the other: each side has
    // its own accumulator. Near-vertical edges are mostly cars' and posts' sides, which
    // stand in a column through the point ahead: they are left out.
    if (std::abs(slope) < kVertical) continue;
    float* const side = slope < 0.0 ? votes_.data() : votes_right_.data();
    const VanishingPoint& r = result_;
    const double rise_scale = 0.25 * camera_.Nv;
    const int last_bin = std::min(bins_y_ - 1, static_cast<int>(std::floor((ay - kMinRise - r.y_lo) / bin_px_)));
    for (int b = 0; b <= last_bin; ++b) {
      const double vy = r.y_lo + (b + 0.5) * bin_px_;
      const double u = (ax + slope * (vy - ay) - r.x_lo) / bin_px_;
      if (!(u >= 0.0 && u < bins_x_)) continue;
      const std::size_t cell = static_cast<std::size_t>(b) * bins_x_ + static_cast<std::size_t>(u);
      // An edge far below a point says more of it than one just below: its direction is
      // extended less far (and the road's edges are the far ones; trees and cars near the
      // horizon are near).
      side[cell] += w * static_cast<float>(std::min(1.0, (ay - vy) / rise_scale));
    }
    ++result_.edges;
  }
}

void VanishingPointFinder::choose_peak() {
  const auto at = [&](const std::vector<float>& v, int b, int u) {
    return static_cast<double>(v[static_cast<std::size_t>(b) * bins_x_ + static_cast<std::size_t>(u)]);
  };
  // A point's score is the geometric mean of its two sides' 3x3 sums: one strong line
  // (a seam, a barrier) votes all along itself, but only lines from both sides cross.
  double best = 0.0, total = 0.0;
  int bb = -1, bu = -1;
  for (int b = 0; b < bins_y_; ++b)
    for (int u = 0; u < bins_x_; ++u) {
      double left = 0.0, right = 0.0;
      for (int i = std::max(0, b - 1); i <= std::min(bins_y_ - 1, b + 1); ++i)
        for (int j = std::max(0, u - 1); j <= std::min(bins_x_ - 1, u + 1); ++j)
          left += at(votes_, i, j), right += at(votes_right_, i, j);
      const double s = std::sqrt(left * right);
      total += s;
      if (s > best) best = s, bb = b, bu = u;
    }
  if (bb < 0) return;
  const double mean = total / (static_cast<double>(bins_x_) * bins_y_);
  // The centroid of the peak's neighbourhood, to a fraction of a bin.
  double sw = 0, sx = 0, sy = 0;
  for (int i = std::max(0, bb - 1); i <= std::min(bins_y_ - 1, bb + 1); ++i)
    for (int j = std::max(0, bu - 1); j <= std::min(bins_x_ - 1, bu + 1); ++j) {
      const double w = at(votes_, i, j) + at(votes_right_, i, j);
      sw += w, sx += w * (j + 0.5), sy += w * (i + 0.5);
    }
  VanishingPoint& r = result_;
  r.x = r.x_lo + sx / sw * bin_px_;
  r.y = r.y_lo + sy / sw * bin_px_;
  r.strength = mean > 0.0 ? best / mean : 0.0;
  r.found = r.strength >= kMinStrength;
}

const VanishingPoint& VanishingPointFinder::find(const ImageView& image, const CameraPose& nominal) {
  result_ = VanishingPoint{};
  bin_px_ = std::max(2.0, 4.0 * camera_.Nu / 1280.0);
  if (image.empty() || image.width != camera_.Nu || image.height != camera_.Nv) return result_;
  set_region(nominal);
  if (!(result_.y_hi > result_.y_lo)) return result_;
  std::fill(votes_.begin(), votes_.end(), 0.0f);
  std::fill(votes_right_.begin(), votes_right_.end(), 0.0f);
  const int first = std::max({1, config_.roi_top_px + 1, static_cast<int>(std::floor(result_.y_lo)) + 8});
  const int end = camera_.Nv - 1 - config_.hood_px;
  for (int y = first; y < end; y += kStep) {
    for (int k = 0; k < 3; ++k) paint_measure_row(image, y - 1 + k, 0, image.width, rows_[k].data());
    vote_row(image, y);
  }
  choose_peak();
  return result_;
}

std::optional<Attitude> attitude_from_vanishing_point(const CameraSpec& camera, const CameraPose& pose, double vp_x,
                                                      double vp_y) {
  // Newton's method on (yaw, pitch) with numerical derivatives: the vanishing point
  // moves smoothly and nearly linearly with both, so a few steps reach it.
  constexpr double kStepRad = 1e-6, kMaxTurn = 30.0 * M_PI / 180.0;
  CameraPose p = pose;
  auto vp = [&](const CameraPose& q, double& x, double& y) {
    return GroundProjector(camera, q).vanishing_point(0, x, y);
  };
  for (int it = 0; it < 20; ++it) {
    double x = 0, y = 0, xa = 0, ya = 0, xb = 0, yb = 0;
    CameraPose a = p, b = p;
    a.attitude.psi += kStepRad;
    b.attitude.theta += kStepRad;
    if (!vp(p, x, y) || !vp(a, xa, ya) || !vp(b, xb, yb)) return std::nullopt;
    const double j11 = (xa - x) / kStepRad, j12 = (xb - x) / kStepRad, j21 = (ya - y) / kStepRad,
                 j22 = (yb - y) / kStepRad;
    const double det = j11 * j22 - j12 * j21;
    if (!(std::abs(det) > 0.0)) return std::nullopt;
    const double ex = vp_x - x, ey = vp_y - y;
    const double dpsi = (j22 * ex - j12 * ey) / det, dtheta = (j11 * ey - j21 * ex) / det;
    p.attitude.psi += dpsi;
    p.attitude.theta += dtheta;
    if (std::abs(p.attitude.psi - pose.attitude.psi) > kMaxTurn ||
        std::abs(p.attitude.theta - pose.attitude.theta) > kMaxTurn)
      return std::nullopt;
    if (std::abs(dpsi) + std::abs(dtheta) < 1e-10) break;
  }
  return p.attitude;
}

}  // namespace ccdlane
