// The chessboard projection against docs/geometry.md's camera model and its own finite differences.
#include "core/calibration/board_projection.hpp"

#include <random>

#include <gtest/gtest.h>

#include "core/geometry/camera_model.hpp"
#include "tests/core/calibration/chessboard_scene.hpp"
#include "tests/core/solver/jacobian_check.hpp"

namespace ccdlane::calibration {
namespace {

TEST(BoardCorners, RowByRowAlongTheColumns) {
  const auto corners = board_corners({3, 2, 25.0});
  ASSERT_EQ(corners.size(), 6u);
  EXPECT_EQ(corners[1], Vec3(25.0, 0.0, 0.0));
  EXPECT_EQ(corners[3], Vec3(0.0, 25.0, 0.0));
  EXPECT_EQ(corners[5], Vec3(50.0, 25.0, 0.0));
}

// The same point through CameraModel (fixed frame, attitude, mount offsets): the film
// frame turned half a turn about its axis, with the origin at the lens, is the board
// projection's camera frame.
TEST(BoardProjection, MatchesTheCameraModel) {
  CameraSpec spec;  // the reference camera of docs/geometry.md
  spec.cx = 410.2;
  spec.cy = 291.7;
  spec.k_px2 = -8.3042e-7;
  spec.yM_mm = -27.25;
  spec.zM_mm = 2.53;
  const CameraPose pose{{deg_to_rad(3.0), deg_to_rad(7.0), deg_to_rad(-2.0)}, 1400.0, 5.05};
  const CameraModel camera(spec, pose);
  const Mat3 half_turn = Vec3(-1.0, -1.0, 1.0).asDiagonal();
  // Fixed frame -> camera frame: p = half_turn T^T (X - L).
  const BoardPose board{half_turn * camera.attitude_matrix().transpose(),
                        -(half_turn * camera.attitude_matrix().transpose() * camera.lens_centre())};
  const Intrinsics in{pose.f_mm, spec.cx, spec.cy, spec.k_px2};
  for (const Vec3& x : {Vec3(8000.0, 1500.0, 0.0), Vec3(15000.0, -3000.0, 0.0), Vec3(6000.0, 0.0, 1200.0)}) {
    const auto expected = camera.pixel_from_point(x);
    const auto got = observed_pixel_of_board_point(spec, in, board, x);
    ASSERT_TRUE(expected && got);
    EXPECT_NEAR(got->x(), expected->x(), 1e-9);
    EXPECT_NEAR(got->y(), expected->y(), 1e-9);
  }
}

TEST(BoardProjection, BehindTheLensHasNoPixel) {
  const CameraSpec spec;
  const BoardPose pose{Mat3::Identity(), Vec3(0.0, 0.0, -10.0)};
  EXPECT_FALSE(observed_pixel_of_board_point(spec, {5.0, 400.5, 300.5, 0.0}, pose, Vec3::Zero()));
}

TEST(BoardProjection, JacobiansMatchFiniteDifferences) {
  const test::ChessboardCamera camera = test::chessboard_camera();
  const BoardGeometry board{9, 6, 25.0};
  std::mt19937 rng(7);
  const auto poses = test::varied_board_poses(camera, board, 3, rng);
  const auto corners = board_corners(board);
  for (const BoardPose& pose : poses)
    for (const Vec3& corner : {corners.front(), corners[22], corners.back()}) {
      IntrinsicsJacobian d_in;
      BoardPoseJacobian d_pose;
      ASSERT_TRUE(observed_pixel_of_board_point(camera.chip, camera.truth, pose, corner, &d_in, &d_pose));
      const double steps[kIntrinsicCount] = {1e-6, 1e-4, 1e-4, 1e-11};
      for (int k = 0; k < kIntrinsicCount; ++k) {
        const auto numeric = test::central_difference(
            [&](double h) {
              Intrinsics in = camera.truth;
              double* fields[] = {&in.f_mm, &in.cx, &in.cy, &in.k_px2};
              *fields[k] += h;
              return Eigen::VectorXd(*observed_pixel_of_board_point(camera.chip, in, pose, corner));
            },
            steps[k]);
        EXPECT_LT((numeric - d_in.col(k)).norm(), 1e-6 * (1.0 + d_in.col(k).norm())) << "intrinsic " << k;
      }
      for (int k = 0; k < kPoseCount; ++k) {
        const auto numeric = test::central_difference(
            [&](double h) {
              Eigen::Matrix<double, kPoseCount, 1> step = Eigen::Matrix<double, kPoseCount, 1>::Zero();
              step(k) = h;
              return Eigen::VectorXd(
                  *observed_pixel_of_board_point(camera.chip, camera.truth, apply_pose_step(pose, step), corner));
            },
            k < 3 ? 1e-7 : 1e-4);
        EXPECT_LT((numeric - d_pose.col(k)).norm(), 1e-5 * (1.0 + d_pose.col(k).norm())) << "pose " << k;
      }
    }
}

TEST(BoardTilt, AngleOfTheNormalFromTheAxis) {
  EXPECT_NEAR(board_tilt_deg({Mat3::Identity(), Vec3(0, 0, 500)}), 0.0, 1e-12);
  EXPECT_NEAR(board_tilt_deg({rotation_from_vector(Vec3(deg_to_rad(30.0), 0, 0)), Vec3(0, 0, 500)}), 30.0, 1e-9);
  // A board seen from behind is as tilted as seen from the front.
  EXPECT_NEAR(board_tilt_deg({rotation_from_vector(Vec3(0, deg_to_rad(160.0), 0)), Vec3(0, 0, 500)}), 20.0, 1e-9);
}

}  // namespace
}  // namespace ccdlane::calibration
