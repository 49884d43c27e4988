// RoadProjection, the solver's fused kernel, against CameraModel::pixel_from_point: the
// same pixel, the same derivatives over the road point and the pose (seen along
// arbitrary pixel directions, as the solver sees them), and the same points rejected.
#include "core/solver/road_projection.hpp"

#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "tests/core/solver/synthetic_scene.hpp"

namespace ccdlane::solver {
namespace {

TEST(RoadProjection, MatchesCameraModelAndItsJacobians) {
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  CameraSpec spec = test::reference_camera();
  spec.cx = 385.0;  // an off-centre principal point too
  constexpr int kPoints = 25;
  RoadProjection projection(spec, kPoints);
  Eigen::ArrayXd xs(kPoints), ys(kPoints), slope(kPoints), b0(kPoints), b1(kPoints), du(kPoints), dv(kPoints);
  Eigen::ArrayXd along(kPoints), across(kPoints);
  RoadProjection::Covectors covectors(kPoints);
  constexpr double kScale = 0.7;
  int compared = 0;
  for (int trial = 0; trial < 40; ++trial) {
    const CameraPose pose{{deg_to_rad(10 * u(rng)), deg_to_rad(3 + 8 * u(rng)), deg_to_rad(10 * u(rng))},
                          1400 + 300 * u(rng),
                          5.05 + 0.5 * u(rng)};
    const CameraModel camera(spec, pose);
    projection.set_pose(pose);
    // The points CameraModel can see, projected together.
    std::vector<Vec3> points;
    while (static_cast<int>(points.size()) < kPoints) {
      const Vec3 X(20000 + 18000 * u(rng), 6000 * u(rng), 0.0);
      if (camera.pixel_from_point(X)) points.push_back(X);
    }
    for (int i = 0; i < kPoints; ++i) {
      xs[i] = points[i].x();
      ys[i] = points[i].y();
      slope[i] = 0.2 * u(rng);
      b0[i] = u(rng);  // an arbitrary pixel-space direction per point
      b1[i] = u(rng);
    }
    ASSERT_TRUE(projection.project(xs, ys, kPoints)) << trial;
    projection.differentiate(slope, kScale, kPoints, du, dv);
    projection.pull_back(b0, b1, kScale, kPoints, covectors);
    for (int i = 0; i < kPoints; ++i) {
      PointJacobian d_point;
      PoseJacobian2 d_pose;
      const Vec2 expected = *camera.pixel_from_point(points[i], &d_point, &d_pose);
      const auto near = [](const Vec2& a, const Vec2& b, const char* what) {
        EXPECT_LE((a - b).norm(), 1e-10 * (1.0 + b.norm())) << what << ": " << a.transpose() << " vs " << b.transpose();
      };
      near(Vec2(projection.u()[i], projection.v()[i]), expected, "pixel");
      near(Vec2(du[i], dv[i]), kScale * (d_point.col(0) + slope[i] * d_point.col(1)), "d/d road direction");
      // Each column seen along b and along b turned a quarter turn.
      const Vec2 b(b0[i], b1[i]), b_turned(-b1[i], b0[i]);
      const auto seen = [&](const Vec2& column) { return Vec2(kScale * b.dot(column), kScale * b_turned.dot(column)); };
      for (int axis = 0; axis < 2; ++axis) {
        projection.road_along(covectors, axis, kPoints, along, across);
        near(Vec2(along[i], across[i]), seen(d_point.col(axis)), "d/d road, seen along b");
      }
      for (int p = 0; p < kPoseParams; ++p) {
        projection.pose_along(covectors, static_cast<PoseParam>(p), kPoints, along, across);
        near(Vec2(along[i], across[i]), seen(d_pose.col(p)), "d/dpose, seen along b");
      }
      ++compared;
    }
  }
  EXPECT_EQ(compared, 40 * kPoints);
}

TEST(RoadProjection, RejectsWhatCameraModelRejects) {
  const CameraSpec spec = test::reference_camera();
  const CameraModel camera(spec, CameraPose{{0.0, deg_to_rad(3.0), 0.0}, 1400.0, 5.05});
  RoadProjection projection(spec, 2);
  projection.set_pose(camera.pose());
  // One point in view and one behind the camera: the batch is refused.
  Eigen::ArrayXd xs(2), ys(2);
  xs << 20000.0, -5000.0;
  ys << 0.0, 0.0;
  EXPECT_TRUE(projection.project(xs, ys, 1));
  EXPECT_FALSE(projection.project(xs, ys, 2));
  EXPECT_FALSE(camera.pixel_from_point(Vec3(-5000.0, 0.0, 0.0)).has_value());
  // Pincushion distortion has an edge of field: beyond it neither gives a pixel.
  CameraSpec pincushion = spec;
  pincushion.k_px2 = 2e-6;
  const CameraModel wide(pincushion, CameraPose{{0.0, deg_to_rad(3.0), 0.0}, 1400.0, 5.05});
  RoadProjection wide_projection(pincushion, 2);
  wide_projection.set_pose(wide.pose());
  xs << 20000.0, 3000.0;
  ys << 0.0, 9000.0;
  EXPECT_FALSE(wide.pixel_from_point(Vec3(3000.0, 9000.0, 0.0)).has_value());
  EXPECT_FALSE(wide_projection.project(xs, ys, 2));
  EXPECT_TRUE(wide_projection.project(xs, ys, 1));
}

}  // namespace
}  // namespace ccdlane::solver
