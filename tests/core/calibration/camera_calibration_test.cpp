// The chessboard fit against synthetic views of known intrinsics: truth within the reported
// sigmas, NEES in its chi-square band, and every refusal.
#include "core/calibration/camera_calibration.hpp"

#include <cmath>
#include <random>
#include <sstream>

#include <Eigen/Cholesky>
#include <gtest/gtest.h>

#include "tests/core/calibration/chessboard_scene.hpp"

namespace ccdlane::calibration {
namespace {

constexpr double kCornerSigmaPx = 0.2;  // a good sub-pixel corner finder on a sharp board

struct Scene {
  test::ChessboardCamera camera = test::chessboard_camera();
  BoardGeometry board{9, 6, 25.0};
  std::vector<BoardView> views;

  Scene(unsigned seed, int count, double sigma_px, double min_tilt_deg = 15.0, double max_tilt_deg = 45.0) {
    std::mt19937 rng(seed);
    for (const BoardPose& pose : test::varied_board_poses(camera, board, count, rng, min_tilt_deg, max_tilt_deg))
      views.push_back({camera.chip.Nu, camera.chip.Nv, test::corner_pixels(camera, board, pose, sigma_px, rng)});
  }
  // Starts far from the truth, as a datasheet guess would.
  CameraCalibration fit() const { return calibrate_camera(camera.chip, 3.0, board, views); }
};

Eigen::Vector4d error_of(const CameraCalibration& c, const Intrinsics& truth) {
  return {c.intrinsics.f_mm - truth.f_mm, c.intrinsics.cx - truth.cx, c.intrinsics.cy - truth.cy,
          c.intrinsics.k_px2 - truth.k_px2};
}

TEST(CameraCalibration, NoiseFreeViewsGiveTheTruth) {
  const Scene scene(1, 6, 0.0);
  const CameraCalibration c = scene.fit();
  ASSERT_EQ(c.status, CalibrationStatus::ok) << c.message;
  const Intrinsics& t = scene.camera.truth;
  EXPECT_NEAR(c.intrinsics.f_mm, t.f_mm, 1e-8 * t.f_mm);
  EXPECT_NEAR(c.intrinsics.cx, t.cx, 1e-6);
  EXPECT_NEAR(c.intrinsics.cy, t.cy, 1e-6);
  EXPECT_NEAR(c.intrinsics.k_px2, t.k_px2, 1e-8 * std::abs(t.k_px2));
  EXPECT_LT(c.rms_px, 1e-6);
}

TEST(CameraCalibration, NoisyViewsGiveTheTruthWithinThreeSigma) {
  const Scene scene(2, 10, kCornerSigmaPx);
  const CameraCalibration c = scene.fit();
  ASSERT_EQ(c.status, CalibrationStatus::ok) << c.message;
  const Eigen::Vector4d e = error_of(c, scene.camera.truth);
  EXPECT_LT(std::abs(e(0)), 3.0 * c.sigma.f_mm);
  EXPECT_LT(std::abs(e(1)), 3.0 * c.sigma.cx);
  EXPECT_LT(std::abs(e(2)), 3.0 * c.sigma.cy);
  EXPECT_LT(std::abs(e(3)), 3.0 * c.sigma.k_px2);
  // The residual sigma estimates the corner noise: with ~960 degrees of freedom its
  // relative standard deviation is ~2.3 %, so 10 % is more than 4 of them.
  EXPECT_NEAR(c.residual_sigma_px, kCornerSigmaPx, 0.1 * kCornerSigmaPx);
  // A mean |r|^2 of 2 sigma^2 per corner, less what the fit absorbed.
  EXPECT_NEAR(c.rms_px, std::sqrt(2.0) * kCornerSigmaPx, 0.1 * kCornerSigmaPx);
  ASSERT_EQ(c.views.size(), 10u);
  for (const ViewResidual& v : c.views) {
    EXPECT_GT(v.tilt_deg, 14.0);
    EXPECT_LT(v.rms_px, 2.0 * std::sqrt(2.0) * kCornerSigmaPx);
  }
}

// Wilson-Hilferty: the chi-square quantile with k degrees of freedom at normal quantile z.
double chi_square_quantile(double k, double z) {
  const double a = 2.0 / (9.0 * k);
  return k * std::pow(1.0 - a + z * std::sqrt(a), 3.0);
}

// The reported covariance is honest: e' C^-1 e summed over independent scenes follows
// chi-square with 4 per scene (a two-sided 99.9 % band).
TEST(CameraCalibration, NeesIsInItsChiSquareBand) {
  constexpr int kScenes = 30;
  double nees_sum = 0.0;
  std::ostringstream report;
  for (int s = 0; s < kScenes; ++s) {
    const Scene scene(100u + static_cast<unsigned>(s), 8, kCornerSigmaPx);
    const CameraCalibration c = scene.fit();
    ASSERT_EQ(c.status, CalibrationStatus::ok) << c.message;
    const Eigen::Vector4d e = error_of(c, scene.camera.truth);
    const double nees = e.dot(c.covariance.ldlt().solve(e));
    nees_sum += nees;
    report << ' ' << nees;
  }
  const double dof = 4.0 * kScenes;
  EXPECT_GT(nees_sum, chi_square_quantile(dof, -3.29)) << report.str();
  EXPECT_LT(nees_sum, chi_square_quantile(dof, 3.29)) << report.str();
}

TEST(CameraCalibration, OneBadCornerShowsInItsView) {
  Scene scene(3, 6, kCornerSigmaPx);
  scene.views[4].corners_px[20] += Vec2(6.0, -4.0);
  const CameraCalibration c = scene.fit();
  ASSERT_EQ(c.status, CalibrationStatus::ok) << c.message;
  for (std::size_t v = 0; v < c.views.size(); ++v)
    if (v != 4) {
      EXPECT_LT(c.views[v].rms_px, c.views[4].rms_px);
    }
}

TEST(CameraCalibration, BoardsFacingTheCameraDoNotDetermineF) {
  const Scene scene(4, 8, kCornerSigmaPx, 0.0, 2.0);
  const CameraCalibration c = scene.fit();
  EXPECT_EQ(c.status, CalibrationStatus::not_determined);
  EXPECT_NE(c.message.find("do not determine f"), std::string::npos) << c.message;
}

TEST(CameraCalibration, SlightTiltsLeaveFTooUncertain) {
  // Tilted a little more than the tilt rule's 3 degrees: the sigma rule refuses.
  const Scene scene(5, 4, 1.0, 3.5, 4.5);
  const CameraCalibration c = scene.fit();
  EXPECT_EQ(c.status, CalibrationStatus::not_determined) << c.sigma.f_mm / c.intrinsics.f_mm;
  EXPECT_NE(c.message.find("sigma"), std::string::npos) << c.message;
}

TEST(CameraCalibration, TwoViewsAreTooFew) {
  const Scene scene(6, 2, kCornerSigmaPx);
  const CameraCalibration c = scene.fit();
  EXPECT_EQ(c.status, CalibrationStatus::too_few_views);
  EXPECT_NE(c.message.find("2 usable view(s), at least 3"), std::string::npos) << c.message;
}

TEST(CameraCalibration, PicturesOfDifferentSizesAreRefused) {
  Scene scene(7, 4, kCornerSigmaPx);
  scene.views[2].width = 800;
  const CameraCalibration c = scene.fit();
  EXPECT_EQ(c.status, CalibrationStatus::mixed_sizes);
  EXPECT_EQ(c.failed_view, 2);
}

TEST(CameraCalibration, PicturesNotOfTheChipSizeAreRefused) {
  Scene scene(8, 4, kCornerSigmaPx);
  for (BoardView& v : scene.views) v.width = 800;
  const CameraCalibration c = scene.fit();
  EXPECT_EQ(c.status, CalibrationStatus::wrong_size);
  EXPECT_NE(c.message.find("800x480"), std::string::npos) << c.message;
}

TEST(CameraCalibration, ViewsWithMissingCornersAreRefused) {
  Scene scene(9, 4, kCornerSigmaPx);
  scene.views[1].corners_px.pop_back();
  const CameraCalibration c = scene.fit();
  EXPECT_EQ(c.status, CalibrationStatus::wrong_corner_count);
  EXPECT_EQ(c.failed_view, 1);
}

}  // namespace
}  // namespace ccdlane::calibration
