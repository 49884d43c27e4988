// Vanishing point from lines of bars: a Hough vote over the bars' ideal centres in
// (direction, crossing of the bottom row), each peak refined by least squares over the
// bars near it, then the point the most lines from both sides pass through.
#include "core/detection/vanishing_lines.hpp"

#include <algorithm>
#include <cmath>

namespace ccdlane {
namespace {

// Lines in normal form: their direction's angle from the vertical (lane lines near the
// car stand steeply in the picture, the next lanes' lean up to 75 degrees; flatter runs
// are shadows, bumpers, dash ends) and their distance from the bottom row's left end
// across them. Half-degree bins keep a line 300 rows long within 3 pixels of its cell.
constexpr int kAngleBins = VanishingLineFinder::kAngleBins;
constexpr double kMaxAngleRad = 75.0 * M_PI / 180.0;
constexpr double kRhoBinPx = 4.0;
// Bars within these of a line are on it: the vote's bins (first), then edge noise and
// the centre of a bar whose width is uneven (least-squares passes).
constexpr double kGatherPx = 6.0;
constexpr double kOnLinePx = 2.5;
constexpr float kMaxBarWeight = 3.0f;      // a bar of high contrast counts as three faint ones
constexpr double kContrastUnit = 20.0;     // grey levels of one unit of weight
constexpr double kPointTolerancePx = 6.0;  // a line passes through a point this near it
constexpr double kChanceSigmas = 4.0;
constexpr double kBesidePx = 40.0;
// A line's least rows and its way below the point (kMinRowSpan, kBelowPointPx) are angles
// of view, set on pictures of this focal length in pixels (TuSimple's 1280x720 camera,
// 1154 px), and scale with a camera's: at 1920x1080 a car's edge 41 rows long (27 at
// 1280x720) made a line and moved the point 40 px. What the bars' sub-pixel scatter
// bounds (the vote's bins, a bar on a line, a line through the point) does not scale.
constexpr double kReferenceFocalPx = 1150.0;
constexpr float kBarsPerRow = 6.0f;
// A line runs to a point above it: its bars reach at least this far below the point, and
// at most this share of the rows they span lie above it (a few bars beyond it are the
// far side's, or clutter near the horizon). Road marks lie between the horizon and the
// picture's bottom; a line of bars that runs on well above the point is a car's edge, a
// pole or a roadside's (TuSimple still 36 from a mount pitched 5 degrees off: a line of
// bars over rows 256-516 and one over rows 254-680, crossing at row 429 of the road,
// outvoted the lane's lines meeting at the horizon, row 247).
constexpr double kBelowPointPx = 20.0;
constexpr double kMaxShareAbovePoint = 0.25;

double angle_of_bin(int j) { return -kMaxAngleRad + (j + 0.5) * (2.0 * kMaxAngleRad / kAngleBins); }

}  // namespace

VanishingLineFinder::VanishingLineFinder(const CameraSpec& camera, int max_bars, const VanishingPointSearch& search)
    : camera_(camera),
      search_(search),
      ix_(static_cast<std::size_t>(max_bars)),
      iy_(static_cast<std::size_t>(max_bars)),
      contrast_w_(static_cast<std::size_t>(max_bars)),
      w_(static_cast<std::size_t>(max_bars)),
      used_(static_cast<std::size_t>(max_bars)),
      row_bars_(static_cast<std::size_t>(camera.Nv)) {
  // rho = x cos(angle) - (y - bottom) sin(angle) lies within [-Nv, Nu + Nv].
  x_lo_ = -camera.Nv;
  x_bins_ = static_cast<int>(std::ceil((camera.Nu + 2.0 * camera.Nv) / kRhoBinPx));
  votes_.resize(static_cast<std::size_t>(kAngleBins) * static_cast<std::size_t>(x_bins_));
  y_bottom_ = camera.Nv;
  for (int j = 0; j < kAngleBins; ++j) {
    cos_[static_cast<std::size_t>(j)] = std::cos(angle_of_bin(j));
    sin_[static_cast<std::size_t>(j)] = std::sin(angle_of_bin(j));
  }
}

void VanishingLineFinder::vote(int delta_sign) {
  for (int i = 0; i < n_; ++i) {
    if (used_[static_cast<std::size_t>(i)] != (delta_sign < 0 ? 2 : 0)) continue;
    const float w = static_cast<float>(delta_sign) * w_[static_cast<std::size_t>(i)];
    const double x = ix_[static_cast<std::size_t>(i)], t = iy_[static_cast<std::size_t>(i)] - y_bottom_;
    for (int j = 0; j < kAngleBins; ++j) {
      const double rho = x * cos_[static_cast<std::size_t>(j)] - t * sin_[static_cast<std::size_t>(j)];
      const double u = (rho - x_lo_) / kRhoBinPx;
      if (!(u >= 0.0 && u < x_bins_)) continue;
      votes_[static_cast<std::size_t>(j) * static_cast<std::size_t>(x_bins_) + static_cast<std::size_t>(u)] += w;
    }
  }
}

int VanishingLineFinder::strongest(int& bi, int& bj) const {
  // The cell of the most votes over 3 x-bins (a line's bars straddle bins).
  float best = 0.0f;
  bi = bj = -1;
  for (int j = 0; j < kAngleBins; ++j) {
    const float* row = votes_.data() + static_cast<std::size_t>(j) * static_cast<std::size_t>(x_bins_);
    for (int i = 1; i + 1 < x_bins_; ++i) {
      const float v = row[i - 1] + row[i] + row[i + 1];
      if (v > best) best = v, bi = i, bj = j;
    }
  }
  return static_cast<int>(best);
}

bool VanishingLineFinder::fit_line(int bi, int bj, BarLine& out) {
  // x = a + b (y - bottom) for the cell's rho and angle.
  double a = (x_lo_ + (bi + 0.5) * kRhoBinPx) / std::cos(angle_of_bin(bj)), b = std::tan(angle_of_bin(bj));
  int count = 0;
  for (int pass = 0; pass < 3; ++pass) {
    const double tol = pass == 0 ? kGatherPx : kOnLinePx;
    double sw = 0, st = 0, sx = 0, stt = 0, stx = 0, weight = 0, top = 1e300, bottom = -1e300;
    count = 0;
    for (int i = 0; i < n_; ++i) {
      if (used_[static_cast<std::size_t>(i)]) continue;
      const double t = iy_[static_cast<std::size_t>(i)] - y_bottom_, x = ix_[static_cast<std::size_t>(i)];
      if (std::abs(x - (a + b * t)) > tol * std::hypot(1.0, b)) continue;  // across the line
      const double w = w_[static_cast<std::size_t>(i)];
      sw += w, st += w * t, sx += w * x, stt += w * t * t, stx += w * t * x;
      weight += w;
      ++count;
      top = std::min(top, iy_[static_cast<std::size_t>(i)]);
      bottom = std::max(bottom, iy_[static_cast<std::size_t>(i)]);
    }
    if (count < kMinBars || bottom - top < kMinRowSpan * angle_px_) return false;
    if (pass > 0 && count < chance_bars(a, b, top, bottom)) return false;
    const double det = sw * stt - st * st;
    if (!(det > 1e-9 * sw * sw)) return false;
    b = (sw * stx - st * sx) / det;
    a = (sx - b * st) / sw;
    out = BarLine{a, b, weight, count, top, bottom};
  }
  if (std::abs(std::atan(b)) > kMaxAngleRad) return false;
  for (int i = 0; i < n_; ++i) {
    const double t = iy_[static_cast<std::size_t>(i)] - y_bottom_;
    if (!used_[static_cast<std::size_t>(i)] &&
        std::abs(ix_[static_cast<std::size_t>(i)] - (a + b * t)) <= kOnLinePx * std::hypot(1.0, b))
      used_[static_cast<std::size_t>(i)] = 2;  // taken: unvoted below, then 1
  }
  return true;
}

double VanishingLineFinder::chance_bars(double x_bottom, double slope, double top, double bottom) const {
  // The bars beside the line (within kBesidePx of it, but not on it) over the rows it
  // spans give the density of clutter where it runs; as many would fall within its band
  // by chance (Poisson), and a line needs this many standard deviations more: the vote
  // takes the best of some 10^4 cells. Near the horizon, where cars and the far road make
  // bars on every row, a line needs many more bars than where the road is clean.
  const double stretch = std::hypot(1.0, slope);
  int beside = 0;
  for (int i = 0; i < n_; ++i) {
    const double y = iy_[static_cast<std::size_t>(i)];
    if (y < top || y > bottom) continue;
    const double d = std::abs(ix_[static_cast<std::size_t>(i)] - (x_bottom + slope * (y - y_bottom_))) / stretch;
    beside += d > kOnLinePx && d <= kBesidePx;
  }
  const double expected = beside * kOnLinePx / (kBesidePx - kOnLinePx);
  return expected + kChanceSigmas * std::sqrt(expected);
}

std::size_t VanishingLineFinder::row_of(int i) const {
  return static_cast<std::size_t>(std::clamp(static_cast<int>(iy_[static_cast<std::size_t>(i)]), 0, camera_.Nv - 1));
}

bool VanishingLineFinder::below(const BarLine& l, double y) const {
  return l.y_bottom >= y + kBelowPointPx * angle_px_ && y - l.y_top <= kMaxShareAbovePoint * (l.y_bottom - l.y_top);
}

double VanishingLineFinder::across(const BarLine& l, double x, double y) const {
  return std::abs(l.x_bottom + l.slope * (y - y_bottom_) - x) / std::hypot(1.0, l.slope);
}

void VanishingLineFinder::choose_point(const VanishingPoint& region) {
  // Every crossing of a line leaning left (below the point, left of it: dx/dy < 0) with
  // one leaning right is a candidate; it scores the geometric mean of the weights of the
  // lines of either side passing within the tolerance of it, above their bars.
  double best = 0.0;
  for (int p = 0; p < num_lines_; ++p)
    for (int q = 0; q < num_lines_; ++q) {
      const BarLine &l = lines_[static_cast<std::size_t>(p)], &r = lines_[static_cast<std::size_t>(q)];
      if (!(l.slope < 0.0 && r.slope > 0.0)) continue;
      const double t = (r.x_bottom - l.x_bottom) / (l.slope - r.slope);
      const double vx = l.x_bottom + l.slope * t, vy = y_bottom_ + t;
      if (vx < region.x_lo || vx > region.x_hi || vy < region.y_lo || vy > region.y_hi) continue;
      double left = 0.0, right = 0.0;
      for (int k = 0; k < num_lines_; ++k) {
        const BarLine& m = lines_[static_cast<std::size_t>(k)];
        if (!below(m, vy)) continue;
        if (across(m, vx, vy) > kPointTolerancePx) continue;
        (m.slope < 0.0 ? left : right) += m.weight;
      }
      const double s = std::sqrt(left * right);
      if (s > best) {
        best = s;
        result_.x = vx, result_.y = vy;
      }
    }
  if (best <= 0.0) return;
  // Refined: the least-squares point of the lines through it (distances across them).
  double a11 = 0, a12 = 0, a22 = 0, b1 = 0, b2 = 0;
  double left = 0.0, right = 0.0;
  for (int k = 0; k < num_lines_; ++k) {
    const BarLine& m = lines_[static_cast<std::size_t>(k)];
    if (!below(m, result_.y) || across(m, result_.x, result_.y) > kPointTolerancePx) continue;
    // The line x - slope (y - yb) = x_bottom, normalised.
    const double nx = 1.0 / std::hypot(1.0, m.slope), ny = -m.slope * nx;
    const double c = (m.x_bottom - m.slope * y_bottom_) * nx, w = m.weight;
    a11 += w * nx * nx, a12 += w * nx * ny, a22 += w * ny * ny, b1 += w * nx * c, b2 += w * ny * c;
    (m.slope < 0.0 ? left : right) += m.weight;
  }
  const double det = a11 * a22 - a12 * a12;
  if (det > 1e-12) {
    result_.x = (a22 * b1 - a12 * b2) / det;
    result_.y = (a11 * b2 - a12 * b1) / det;
  }
  result_.strength = std::sqrt(left * right);
  result_.found = left >= kMinSideWeight && right >= kMinSideWeight;
}

void VanishingLineFinder::add(std::span<const MarkCandidate> bars, std::span<const float> row_shares) {
  for (const MarkCandidate& m : bars) {
    if (n_ >= static_cast<int>(ix_.size())) return;
    const auto i = static_cast<std::size_t>(n_++);
    const double dx = m.px() - camera_.cx, dy = m.py - camera_.cy;
    const double den = 1.0 + camera_.k_px2 * (dx * dx + dy * dy);
    const double s = den > 0.0 ? 1.0 / den : 1.0;
    ix_[i] = camera_.cx + dx * s;
    iy_[i] = camera_.cy + dy * s;
    // Paint in a dim picture or a shadow stands above its road by the light's share of
    // daylight's contrast, as its threshold does: weighed in grey levels, a dim road's
    // lines fell short of a line's votes while a car's lit edge did not (a TuSimple still
    // at a third of its light took a car's edge for a lane line).
    const auto row = static_cast<std::size_t>(m.scan_row);
    const double share = row < row_shares.size() && row_shares[row] > 0.0f ? static_cast<double>(row_shares[row]) : 1.0;
    contrast_w_[i] = std::min(kMaxBarWeight, static_cast<float>(m.contrast / (kContrastUnit * share)));
  }
}

const VanishingPoint& VanishingLineFinder::find(const CameraPose& nominal) {
  result_ = VanishingPoint{};
  num_lines_ = 0;
  angle_px_ = nominal.f_mm / camera_.pitch_u() / kReferenceFocalPx;
  set_search_region(camera_, nominal, search_, result_);
  std::fill(used_.begin(), used_.end(), 0);
  result_.edges = n_;
  // Each row's bars share its vote beyond kBarsPerRow of them: near the horizon, cars, the
  // far road and the roadside make a bar every few pixels of a row, and lines drawn
  // through such rows would outvote the lane lines below them, which give a few bars a row.
  std::fill(row_bars_.begin(), row_bars_.end(), 0);
  for (int i = 0; i < n_; ++i) ++row_bars_[row_of(i)];
  for (int i = 0; i < n_; ++i)
    w_[static_cast<std::size_t>(i)] = contrast_w_[static_cast<std::size_t>(i)] *
                                      std::min(1.0f, kBarsPerRow / static_cast<float>(row_bars_[row_of(i)]));
  std::fill(votes_.begin(), votes_.end(), 0.0f);
  vote(+1);
  for (int attempt = 0; attempt < 2 * kMaxLines && num_lines_ < kMaxLines; ++attempt) {
    int bi = -1, bj = -1;
    if (strongest(bi, bj) < kMinBars) break;
    BarLine l;
    if (fit_line(bi, bj, l)) {
      lines_[static_cast<std::size_t>(num_lines_++)] = l;
      vote(-1);  // the line's bars (used_ 2) vote no more
      for (char& u : used_) u = u ? 1 : 0;
      continue;
    }
    for (int j = std::max(0, bj - 1); j <= std::min(kAngleBins - 1, bj + 1); ++j)
      for (int i = std::max(0, bi - 1); i <= std::min(x_bins_ - 1, bi + 1); ++i)
        votes_[static_cast<std::size_t>(j) * static_cast<std::size_t>(x_bins_) + static_cast<std::size_t>(i)] = 0.0f;
  }
  choose_point(result_);
  return result_;
}

}  // namespace ccdlane
