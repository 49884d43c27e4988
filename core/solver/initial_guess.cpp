// Initial values from the picks themselves, so a cold start needs no prior lane model.
#include "core/solver/initial_guess.hpp"

#include <array>
#include <cmath>
#include <limits>

namespace ccdlane::solver {

int ground_points_of_picks(const CameraSpec& spec, const CameraPose& pose, std::span<const Pick> picks, Vec2* ground) {
  // CameraModel::ground_point_from_pixel for every pick in one branch-free pass (this
  // runs on every solve). The ray from the cell at chip position c (film frame) through
  // the lens runs along r = T (c, -f), and c is the undistorted offset v / (1 + k |v|^2)
  // times the pitch, so r ~ T (v_x p_u, v_y p_v, -f (1 + k |v|^2)): the distortion's
  // division cancels in the intersection with the road, L - L_z r_xy / r_z.
  const Mat3 T = attitude_matrix(pose.attitude);  // not CameraModel: no derivatives needed
  const Vec3 L = Vec3(0.0, 0.0, pose.H_mm) + T * CameraModel::lens_in_film(spec, pose.f_mm);
  const double cx = spec.cx, cy = spec.cy, k = spec.k_px2, pu = spec.pitch_u(), pv = spec.pitch_v();
  const double f = pose.f_mm;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const int n = static_cast<int>(picks.size());
#pragma GCC ivdep
  for (int i = 0; i < n; ++i) {
    const double vx = picks[i].px - cx, vy = picks[i].py - cy;
    const double scale = 1.0 + k * (vx * vx + vy * vy);  // > 0 inside the model's field
    const double a = vx * pu, b = vy * pv, c = -f * scale;
    const double rz = T(2, 0) * a + T(2, 1) * b + T(2, 2) * c;
    // The ray reaches the road only going down from the lens: the cell above it.
    const bool seen = (scale > 0.0) & (rz * scale > 0.0);
    const double t = (seen ? L.z() : nan) / rz;
    ground[i] = Vec2(L.x() - t * (T(0, 0) * a + T(0, 1) * b + T(0, 2) * c),
                     L.y() - t * (T(1, 0) * a + T(1, 1) * b + T(1, 2) * c));
  }
  for (int i = 0; i < n; ++i)
    if (std::isnan(ground[i].x())) return i;
  return -1;
}

void fit_initial_lines(std::span<const Pick> picks, const Vec2* ground, int num_lines, bool fit_slope,
                       RoadLine* lines) {
  // Sums for the normal equations of y = y0 + m x, per line.
  struct Sums {
    double n = 0, x = 0, y = 0, xx = 0, xy = 0;
  };
  std::array<Sums, kMaxLaneLines> s{};
  for (std::size_t i = 0; i < picks.size(); ++i) {
    Sums& t = s[picks[i].line];
    const double x = ground[i].x(), y = ground[i].y();
    t.n += 1;
    t.x += x;
    t.y += y;
    t.xx += x * x;
    t.xy += x * y;
  }
  for (int j = 0; j < num_lines; ++j) {
    const Sums& t = s[j];
    RoadLine& line = lines[j];
    line = RoadLine{};
    if (t.n == 0) continue;
    const double det = t.n * t.xx - t.x * t.x;  // n^2 times the variance of x
    if (fit_slope && det > 1e-9 * t.n * t.xx) {
      line.m = (t.n * t.xy - t.x * t.y) / det;
      line.y0_mm = (t.y - line.m * t.x) / t.n;
    } else {
      line.y0_mm = t.y / t.n;
    }
  }
}

}  // namespace ccdlane::solver
