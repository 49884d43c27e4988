// Synthetic lane scenes with known truth for the solver's tests and benchmarks: the
// reference camera of docs/geometry.md at road scale, marks projected from the truth.
#pragma once

#include <cstdint>
#include <initializer_list>
#include <random>
#include <vector>

#include "app/config.hpp"
#include "core/solver/lane_solver.hpp"

namespace ccdlane::test {

struct SceneOptions {
  int num_picks = 30;
  int num_lines = 2;
  double max_angle_deg = 5.0;  // |psi|, |theta|, |phi| of the truth
  double max_slope = 0.0;      // |m| of the truth (0: lines along x)
  double max_curvature = 0.0;  // |c| of the truth, 1/mm
  // A bend instead (when max_radius_mm > 0): one curvature c = +-1 / (2 R) shared by all
  // lines (left or right at random), R uniform in [min_radius_mm, max_radius_mm].
  double min_radius_mm = 0.0;
  double max_radius_mm = 0.0;
  double min_ahead_mm = 5000.0;
  double max_ahead_mm = 40000.0;
  // Non-empty: marks only at these distances ahead (in turn), none in between.
  std::vector<double> mark_distances_mm;
};

struct SyntheticScene {
  CameraSpec camera;
  CameraPose truth;
  std::vector<RoadLine> lines;
  std::vector<double> x_mm;  // each mark's truth distance ahead
  std::vector<Pick> picks;   // exact projections of the marks
};

// The reference camera (DH-HV2003UC, f = 5.05 mm, k = -8.3042e-7) of docs/geometry.md.
CameraSpec reference_camera();

// A random scene: H 1.2-1.6 m, lines 3-4 m apart around the camera, marks on every
// line in turn, 5-40 m ahead, kept only where they fall inside the picture.
SyntheticScene make_scene(std::mt19937_64& rng, const SceneOptions& options);

// Picks of `scene` with independent Gaussian noise of `sigma_px` on each coordinate.
std::vector<Pick> noisy_picks(const SyntheticScene& scene, double sigma_px, std::mt19937_64& rng);

// A small scene of 8 marks on two gently curved, slanted lines: every line parameter
// matters, for checking residuals and Jacobians.
SyntheticScene small_curved_scene(std::uint64_t seed);

FreeSet free_set(std::initializer_list<FreeParam> params);
FreeSet all_free();

}  // namespace ccdlane::test
