// Starting values: ray-ground points of the picks and the per-line straight-line fit.
#include "core/solver/initial_guess.hpp"

#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "tests/core/solver/synthetic_scene.hpp"

namespace ccdlane::solver {
namespace {

TEST(InitialGuess, GroundPointsAtTheTruePoseAreTheMarks) {
  std::mt19937_64 rng(1);
  const test::SyntheticScene scene = test::make_scene(rng, {});
  const CameraModel camera(scene.camera, scene.truth);
  std::vector<Vec2> ground(scene.picks.size());
  EXPECT_EQ(ground_points_of_picks(camera.spec(), camera.pose(), scene.picks, ground.data()), -1);
  for (std::size_t i = 0; i < ground.size(); ++i) {
    EXPECT_NEAR(ground[i].x(), scene.x_mm[i], 1e-6 * scene.x_mm[i]);
    EXPECT_NEAR(ground[i].y(), scene.lines[scene.picks[i].line].y0_mm, 1e-6 * scene.x_mm[i]);
  }
}

// The batch computation (one pass, the distortion's division cancelled) against
// CameraModel::ground_point_from_pixel, pick by pick: the same points and the same misses,
// over poses, an off-centre principal point and both signs of distortion.
TEST(InitialGuess, GroundPointsAreCameraModelsOwn) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  CameraSpec spec = test::reference_camera();
  spec.cx = 385.0;
  int compared = 0, missed = 0;
  for (const double k : {0.0, 4e-7, -5e-6}) {
    spec.k_px2 = k;
    for (int trial = 0; trial < 20; ++trial) {
      const CameraPose pose{{deg_to_rad(10 * u(rng)), deg_to_rad(3 + 8 * u(rng)), deg_to_rad(10 * u(rng))},
                            1400 + 300 * u(rng),
                            5.05 + 0.5 * u(rng)};
      const CameraModel camera(spec, pose);
      std::vector<Pick> picks;
      for (int i = 0; i < 40; ++i) picks.push_back({0, 400.0 + 400.0 * u(rng), 300.0 + 300.0 * u(rng)});
      std::vector<Vec2> ground(picks.size());
      const int first_miss = ground_points_of_picks(camera.spec(), camera.pose(), picks, ground.data());
      int expected_miss = -1;
      for (std::size_t i = 0; i < picks.size(); ++i) {
        const auto g = camera.ground_point_from_pixel(Vec2(picks[i].px, picks[i].py));
        if (!g) {
          if (expected_miss < 0) expected_miss = static_cast<int>(i);
          continue;
        }
        EXPECT_LE((ground[i] - g->head<2>()).norm(), 1e-9 * g->head<2>().norm()) << "pick " << i;
        ++compared;
      }
      EXPECT_EQ(first_miss, expected_miss);
      missed += expected_miss >= 0;
    }
  }
  // Both outcomes occurred: rows above the horizon, and the barrel model's edge of field.
  EXPECT_GT(compared, 200);
  EXPECT_GT(missed, 10);
}

TEST(InitialGuess, PickAboveTheHorizonIsNamed) {
  std::mt19937_64 rng(2);
  test::SyntheticScene scene = test::make_scene(rng, {});
  scene.picks[2].py = 1.0;  // top row: sky for any attitude within a few degrees
  const CameraModel camera(scene.camera, scene.truth);
  std::vector<Vec2> ground(scene.picks.size());
  EXPECT_EQ(ground_points_of_picks(camera.spec(), camera.pose(), scene.picks, ground.data()), 2);
}

TEST(InitialGuess, LineFitRecoversStraightLinesExactly) {
  const std::vector<Pick> picks = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}, {1, 0, 0}, {1, 0, 0}, {2, 0, 0}};
  const std::vector<Vec2> ground = {{5000, 1800},  {10000, 1850},  {20000, 1950},  // y = 1750 + 0.01 x
                                    {6000, -1760}, {30000, -1880},                 // y = -1730 - 0.005 x
                                    {8000, 100}};
  RoadLine lines[4];
  fit_initial_lines(picks, ground.data(), 4, true, lines);
  EXPECT_NEAR(lines[0].y0_mm, 1750.0, 1e-9);
  EXPECT_NEAR(lines[0].m, 0.01, 1e-12);
  EXPECT_NEAR(lines[1].y0_mm, -1730.0, 1e-9);
  EXPECT_NEAR(lines[1].m, -0.005, 1e-12);
  EXPECT_DOUBLE_EQ(lines[2].y0_mm, 100.0);  // a single point: no slope
  EXPECT_DOUBLE_EQ(lines[2].m, 0.0);
  EXPECT_DOUBLE_EQ(lines[3].y0_mm, 0.0);  // no picks
  EXPECT_DOUBLE_EQ(lines[0].c_per_mm, 0.0);
  // With m fixed (at 0) the offset is the mean lateral position.
  fit_initial_lines(picks, ground.data(), 4, false, lines);
  EXPECT_DOUBLE_EQ(lines[0].m, 0.0);
  EXPECT_NEAR(lines[0].y0_mm, (1800.0 + 1850.0 + 1950.0) / 3.0, 1e-9);
}

}  // namespace
}  // namespace ccdlane::solver
