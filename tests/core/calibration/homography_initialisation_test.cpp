// Zhang's start on noise-free, undistorted views: the focal length and poses come back exactly.
#include "core/calibration/homography_initialisation.hpp"

#include <random>

#include <gtest/gtest.h>

#include "tests/core/calibration/chessboard_scene.hpp"

namespace ccdlane::calibration {
namespace {

struct UndistortedViews {
  test::ChessboardCamera camera = test::chessboard_camera();
  BoardGeometry board{9, 6, 25.0};
  std::vector<Vec3> corners = board_corners(board);
  std::vector<BoardPose> poses;
  std::vector<Mat3> homographies;

  explicit UndistortedViews(double min_tilt_deg, double max_tilt_deg) {
    camera.truth.k_px2 = 0.0;
    std::mt19937 rng(11);
    poses = test::varied_board_poses(camera, board, 5, rng, min_tilt_deg, max_tilt_deg);
    for (const BoardPose& pose : poses) {
      const auto pixels = test::corner_pixels(camera, board, pose, 0.0, rng);
      homographies.push_back(*board_to_chip_homography(camera.chip, camera.truth.cx, camera.truth.cy, corners, pixels));
    }
  }
};

TEST(HomographyInitialisation, RecoversFocalLengthAndPoses) {
  const UndistortedViews v(15.0, 45.0);
  const auto f = focal_length_from_homographies(v.homographies);
  ASSERT_TRUE(f);
  EXPECT_NEAR(*f, v.camera.truth.f_mm, 1e-9 * v.camera.truth.f_mm);
  for (std::size_t i = 0; i < v.poses.size(); ++i) {
    const BoardPose pose = pose_from_homography(v.homographies[i], *f);
    EXPECT_LT((pose.rotation - v.poses[i].rotation).norm(), 1e-8);
    EXPECT_LT((pose.translation_mm - v.poses[i].translation_mm).norm(), 1e-6);
  }
}

TEST(HomographyInitialisation, BoardsFacingTheCameraGiveNoFocalLength) {
  const UndistortedViews v(0.0, 0.0);
  EXPECT_FALSE(focal_length_from_homographies(v.homographies));
}

TEST(HomographyInitialisation, TooFewCornersGiveNoHomography) {
  const CameraSpec chip;
  const std::vector<Vec3> board{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  const std::vector<Vec2> pixels{{1, 1}, {2, 1}, {1, 2}};
  EXPECT_FALSE(board_to_chip_homography(chip, 400.5, 300.5, board, pixels));
}

TEST(HomographyInitialisation, CollinearCornersGiveNoHomography) {
  const CameraSpec chip;
  const std::vector<Vec3> board{{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}, {4, 0, 0}};
  const std::vector<Vec2> pixels{{1, 1}, {2, 1}, {3, 1}, {4, 1}, {5, 1}};
  EXPECT_FALSE(board_to_chip_homography(chip, 400.5, 300.5, board, pixels));
}

}  // namespace
}  // namespace ccdlane::calibration
