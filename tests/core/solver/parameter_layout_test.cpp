// ParameterLayout: where each free unknown sits, and how steps map back onto poses/lines.
#include "core/solver/parameter_layout.hpp"

#include <gtest/gtest.h>

#include "tests/core/solver/synthetic_scene.hpp"

namespace ccdlane::solver {
namespace {

using test::free_set;

TEST(ParameterLayout, GlobalsFirstThenEachLinesKinds) {
  using enum FreeParam;
  const ParameterLayout layout(free_set({phi, psi, f, c, y0}), 3);
  EXPECT_EQ(layout.num_global(), 3);
  EXPECT_EQ(layout.num_line_kinds(), 2);
  EXPECT_EQ(layout.size(), 3 + 2 * 3);
  EXPECT_EQ(layout.local_size(), 5);
  EXPECT_EQ(layout.global(0), kPsi);  // psi theta phi H f order, whatever the set's order
  EXPECT_EQ(layout.global(1), kPhi);
  EXPECT_EQ(layout.global(2), kFocal);
  EXPECT_EQ(layout.global_index(kPhi), 1);
  EXPECT_EQ(layout.global_index(kTheta), -1);
  EXPECT_EQ(layout.line_index(0, kY0), 3);
  EXPECT_EQ(layout.line_index(0, kCurvature), 4);
  EXPECT_EQ(layout.line_index(2, kY0), 7);
  EXPECT_EQ(layout.line_index(1, kSlope), -1);
  const ReducedParam p = layout.describe(6);
  EXPECT_EQ(p.kind, c);
  EXPECT_EQ(p.line, 1);
  EXPECT_EQ(layout.describe(2).kind, f);
  EXPECT_EQ(layout.describe(2).line, -1);
}

TEST(ParameterLayout, StepsLandOnTheirParametersOnly) {
  using enum FreeParam;
  const ParameterLayout layout(free_set({theta, H, m}), 2);
  CameraPose pose{{0.1, 0.2, 0.3}, 1400.0, 5.05};
  RoadLine lines[2] = {{1750.0, 0.01, 1e-6}, {-1750.0, 0.02, 2e-6}};
  ReducedVector step(layout.size());
  step << 0.5, 10.0, 0.001, 0.002;
  layout.apply_step(step, pose, lines);
  EXPECT_DOUBLE_EQ(pose.attitude.psi, 0.1);
  EXPECT_DOUBLE_EQ(pose.attitude.theta, 0.7);
  EXPECT_DOUBLE_EQ(pose.attitude.phi, 0.3);
  EXPECT_DOUBLE_EQ(pose.H_mm, 1410.0);
  EXPECT_DOUBLE_EQ(pose.f_mm, 5.05);
  EXPECT_DOUBLE_EQ(lines[0].m, 0.011);
  EXPECT_DOUBLE_EQ(lines[1].m, 0.022);
  EXPECT_DOUBLE_EQ(lines[1].y0_mm, -1750.0);
  EXPECT_DOUBLE_EQ(layout.squared_norm(pose, lines), 0.7 * 0.7 + 1410.0 * 1410.0 + 0.011 * 0.011 + 0.022 * 0.022);

  // Line 1's local parameters: the two globals, then its own slope.
  EXPECT_EQ(layout.reduced_index(1, 0), 0);
  EXPECT_EQ(layout.reduced_index(1, 1), 1);
  EXPECT_EQ(layout.reduced_index(1, 2), 3);
  EXPECT_EQ(layout.reduced_index(0, 2), 2);
  EXPECT_EQ(step[layout.reduced_index(1, 2)], 0.002);
}

TEST(ParameterLayout, SharedCurvatureIsOneGlobalAfterThePose) {
  using enum FreeParam;
  // c in the free set is ignored here (LaneSolver refuses the combination).
  const ParameterLayout layout(free_set({psi, theta, y0, c}), 3, LineModel::shared_curvature);
  EXPECT_EQ(layout.num_pose(), 2);
  EXPECT_EQ(layout.num_global(), 3);
  EXPECT_EQ(layout.num_line_kinds(), 1);
  EXPECT_EQ(layout.size(), 3 + 3);
  EXPECT_EQ(layout.local_size(), 4);
  EXPECT_EQ(layout.shared_curvature_index(), 2);
  EXPECT_EQ(layout.line_index(1, kCurvature), -1);
  EXPECT_EQ(layout.line_index(1, kY0), 4);
  EXPECT_EQ(layout.global_index(kPhi), -1);
  EXPECT_EQ(layout.describe(2).kind, c);
  EXPECT_EQ(layout.describe(2).line, -1);
  EXPECT_EQ(layout.describe(5).kind, y0);
  EXPECT_EQ(layout.describe(5).line, 2);
  EXPECT_EQ(layout.reduced_index(2, 2), 2);  // every line's local column 2 is the shared c
  EXPECT_EQ(ParameterLayout(free_set({psi, y0}), 2).shared_curvature_index(), -1);

  CameraPose pose{{0.1, 0.2, 0.3}, 1400.0, 5.05};
  RoadLine lines[3] = {{1750.0, 0.0, 1e-6}, {-1750.0, 0.0, 1e-6}, {-5250.0, 0.0, 1e-6}};
  ReducedVector step(layout.size());
  step << 0.5, 0.25, 2e-6, 10.0, 20.0, 30.0;
  layout.apply_step(step, pose, lines);
  for (const RoadLine& l : lines) EXPECT_DOUBLE_EQ(l.c_per_mm, 3e-6);
  EXPECT_DOUBLE_EQ(lines[2].y0_mm, -5220.0);
  EXPECT_DOUBLE_EQ(pose.attitude.theta, 0.45);
  // The shared c counts once in the parameters' norm.
  const double y0s = 1760.0 * 1760.0 + 1730.0 * 1730.0 + 5220.0 * 5220.0;
  EXPECT_DOUBLE_EQ(layout.squared_norm(pose, lines), 0.6 * 0.6 + 0.45 * 0.45 + 3e-6 * 3e-6 + y0s);
}

}  // namespace
}  // namespace ccdlane::solver
