// RoadProjection, the solver's fused kernel, against CameraModel::pixel_from_point: the
// same pixel and the same derivatives over the road point and the pose, and the same
// points rejected.
#include "core/solver/road_projection.hpp"

#include <random>

#include <gtest/gtest.h>

#include "tests/core/solver/synthetic_scene.hpp"

namespace ccdlane::solver {
namespace {

TEST(RoadProjection, MatchesCameraModelAndItsJacobians) {
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  CameraSpec spec = test::reference_camera();
  spec.cx = 385.0;  // an off-centre principal point too
  int compared = 0;
  for (int trial = 0; trial < 500; ++trial) {
    const CameraPose pose{{deg_to_rad(10 * u(rng)), deg_to_rad(3 + 8 * u(rng)), deg_to_rad(10 * u(rng))},
                          1400 + 300 * u(rng), 5.05 + 0.5 * u(rng)};
    const CameraModel camera(spec, pose);
    RoadProjection projection;
    projection.set_camera(camera);
    const Vec3 X(20000 + 18000 * u(rng), 6000 * u(rng), 0.0);
    PointJacobian d_point;
    PoseJacobian2 d_pose;
    const auto expected = camera.pixel_from_point(X, &d_point, &d_pose);
    RoadProjection::Chain chain;
    ASSERT_EQ(projection.start(X.x(), X.y(), chain), expected.has_value()) << trial;
    if (!expected) continue;
    ++compared;
    const auto near = [](const Vec2& a, const Vec2& b, const char* what) {
      EXPECT_LE((a - b).norm(), 1e-10 * (1.0 + b.norm())) << what << ": " << a.transpose() << " vs " << b.transpose();
    };
    near(projection.pixel(chain), *expected, "pixel");
    RoadProjection::Derivatives d;
    projection.derivatives(chain, d);
    near(projection.road_column(d, 0), d_point.col(0), "d/dx");
    near(projection.road_column(d, 1), d_point.col(1), "d/dy");
    for (int p = 0; p < kPoseParams; ++p)
      near(projection.pose_column(d, static_cast<PoseParam>(p)), d_pose.col(p), "d/dpose");
  }
  EXPECT_GT(compared, 400);
}

TEST(RoadProjection, RejectsWhatCameraModelRejects) {
  const CameraSpec spec = test::reference_camera();
  const CameraModel camera(spec, CameraPose{{0.0, deg_to_rad(3.0), 0.0}, 1400.0, 5.05});
  RoadProjection projection;
  projection.set_camera(camera);
  RoadProjection::Chain chain;
  EXPECT_FALSE(projection.start(-5000.0, 0.0, chain));  // behind the camera
  EXPECT_FALSE(camera.pixel_from_point(Vec3(-5000.0, 0.0, 0.0)).has_value());
  // Pincushion distortion has an edge of field: beyond it neither gives a pixel.
  CameraSpec pincushion = spec;
  pincushion.k_px2 = 2e-6;
  const CameraModel wide(pincushion, CameraPose{{0.0, deg_to_rad(3.0), 0.0}, 1400.0, 5.05});
  projection.set_camera(wide);
  const Vec3 far_side(3000.0, 9000.0, 0.0);
  EXPECT_EQ(projection.start(far_side.x(), far_side.y(), chain), wide.pixel_from_point(far_side).has_value());
  EXPECT_FALSE(projection.start(far_side.x(), far_side.y(), chain));
}

}  // namespace
}  // namespace ccdlane::solver
