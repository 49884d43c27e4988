// Initial values from the picks themselves, so a cold start needs no prior lane model.
#include "core/solver/initial_guess.hpp"

#include <array>

namespace ccdlane::solver {

int ground_points_of_picks(const CameraModel& camera, std::span<const Pick> picks, Vec2* ground) {
  for (std::size_t i = 0; i < picks.size(); ++i) {
    const auto g = camera.ground_point_from_pixel(Vec2(picks[i].px, picks[i].py));
    if (!g) return static_cast<int>(i);
    ground[i] = g->head<2>();
  }
  return -1;
}

void fit_initial_lines(std::span<const Pick> picks, const Vec2* ground, int num_lines, bool fit_slope,
                       LaneLine* lines) {
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
    LaneLine& line = lines[j];
    line = LaneLine{};
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
