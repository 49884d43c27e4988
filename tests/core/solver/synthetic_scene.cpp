// Scene generation: uniform draws in the ranges the solver meets on a road.
#include "tests/core/solver/synthetic_scene.hpp"

#include <stdexcept>

namespace ccdlane::test {

CameraSpec reference_camera() { return default_config().camera; }

SyntheticScene make_scene(std::mt19937_64& rng, const SceneOptions& o) {
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  SyntheticScene s;
  s.camera = reference_camera();
  const double a = deg_to_rad(o.max_angle_deg);
  s.truth.attitude = {a * unit(rng), a * unit(rng), a * unit(rng)};
  s.truth.H_mm = 1400.0 + 200.0 * unit(rng);
  s.truth.f_mm = 5.05;
  const double spacing = 3500.0 + 500.0 * unit(rng);
  const double centre = 500.0 * unit(rng);  // the camera is somewhere within its lane
  double bend_c = 0.0;
  if (o.max_radius_mm > 0.0) {
    const double radius = o.min_radius_mm + (o.max_radius_mm - o.min_radius_mm) * (unit(rng) + 1.0) / 2.0;
    bend_c = (unit(rng) < 0.0 ? -1.0 : 1.0) / (2.0 * radius);
  }
  for (int j = 0; j < o.num_lines; ++j) {
    RoadLine l;
    l.y0_mm = centre + spacing * ((o.num_lines - 1) / 2.0 - j);  // left (largest y0) first
    l.m = o.max_slope * unit(rng);
    l.c_per_mm = o.max_radius_mm > 0.0 ? bend_c : o.max_curvature * unit(rng);
    s.lines.push_back(l);
  }
  const CameraModel camera(s.camera, s.truth);
  std::uniform_real_distribution<double> ahead(o.min_ahead_mm, o.max_ahead_mm);
  for (int i = 0, tries = 0; i < o.num_picks; ++tries) {
    if (tries > 100000) throw std::runtime_error("make_scene: marks do not fall into the picture");
    const int j = i % o.num_lines;
    const RoadLine& l = s.lines[j];
    const std::size_t n_at = o.mark_distances_mm.size();
    const double x = n_at > 0 ? o.mark_distances_mm[(i / o.num_lines) % n_at] : ahead(rng);
    const auto px = camera.pixel_from_point(Vec3(x, l.y0_mm + l.m * x + l.c_per_mm * x * x, 0.0));
    // Keep a margin so that noisy picks stay on the chip too.
    if (!px || px->x() < 5 || px->x() > s.camera.Nu - 4 || px->y() < 5 || px->y() > s.camera.Nv - 4) continue;
    s.x_mm.push_back(x);
    s.picks.push_back({j, px->x(), px->y()});
    ++i;
  }
  return s;
}

std::vector<Pick> noisy_picks(const SyntheticScene& scene, double sigma_px, std::mt19937_64& rng) {
  std::normal_distribution<double> noise(0.0, sigma_px);
  std::vector<Pick> picks = scene.picks;
  for (Pick& p : picks) {
    p.px += noise(rng);
    p.py += noise(rng);
  }
  return picks;
}

SyntheticScene small_curved_scene(std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  SceneOptions o;
  o.num_picks = 8;
  o.max_slope = 0.02;
  o.max_curvature = 1e-6;
  return make_scene(rng, o);
}

FreeSet free_set(std::initializer_list<FreeParam> params) {
  FreeSet s;
  for (FreeParam p : params) s.add(p);
  return s;
}

FreeSet all_free() {
  FreeSet s;
  for (int p = 0; p < kFreeParamCount; ++p) s.add(static_cast<FreeParam>(p));
  return s;
}

}  // namespace ccdlane::test
