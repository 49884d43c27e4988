// CameraModel against the specification's worked numbers, plus property tests: round
// trips over random poses and analytic Jacobians against central finite differences.
#include "core/geometry/camera_model.hpp"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "tests/core/geometry_vectors.hpp"

namespace ccdlane {
namespace {

// |a - b| <= rel * max(|b|, floor): relative, with an absolute floor for values near 0
// (e.g. a ground z of 2e-13 in the vectors file is 0 up to rounding).
void expect_close(double a, double b, double rel, double floor, const std::string& what) {
  EXPECT_LE(std::abs(a - b), rel * std::max(std::abs(b), floor)) << what << ": got " << a << " want " << b;
}

TEST(CameraModelVectors, AttitudeChipOriginAndLensCentre) {
  for (const auto& c : test::load_geometry_vectors()) {
    const CameraModel cam(c.spec, c.pose);
    for (int r = 0; r < 3; ++r)
      for (int k = 0; k < 3; ++k) expect_close(cam.attitude_matrix()(r, k), c.raw["T"][r][k], 1e-9, 1.0, "T");
    for (int i = 0; i < 3; ++i) {
      expect_close(cam.chip_origin()[i], c.raw["O_F_mm"][i], 1e-9, 1.0, "O_F");
      expect_close(cam.lens_centre()[i], c.raw["L_mm"][i], 1e-9, 1.0, "L");
    }
  }
}

TEST(CameraModelVectors, GroundToPixel) {
  for (const auto& c : test::load_geometry_vectors()) {
    const CameraModel cam(c.spec, c.pose);
    for (const auto& p : c.raw["points"]) {
      const Vec3 ground(p["ground_mm"][0], p["ground_mm"][1], p["ground_mm"][2]);
      const auto px = cam.pixel_from_point(ground);
      ASSERT_TRUE(px.has_value());
      expect_close(px->x(), p["pixel"][0], 1e-9, 1.0, "Px");
      expect_close(px->y(), p["pixel"][1], 1e-9, 1.0, "Py");
    }
  }
}

TEST(CameraModelVectors, PixelToGround) {
  for (const auto& c : test::load_geometry_vectors()) {
    const CameraModel cam(c.spec, c.pose);
    for (const auto& p : c.raw["pixel_to_ground"]) {
      const auto g = cam.ground_point_from_pixel(Vec2(p["pixel"][0], p["pixel"][1]));
      ASSERT_TRUE(g.has_value());
      for (int i = 0; i < 3; ++i) expect_close((*g)[i], p["ground_mm"][i], 1e-9, 1.0, "ground");
    }
  }
}

// Random poses of the kind ccdlane meets, plus steeper ones.
struct RandomScene {
  std::mt19937_64 rng{12345};
  CameraSpec spec() {
    CameraSpec s;
    s.k_px2 = std::uniform_real_distribution<>(-1.5e-6, 4e-7)(rng);
    s.cx = 400.5 + std::uniform_real_distribution<>(-20, 20)(rng);
    s.cy = 300.5 + std::uniform_real_distribution<>(-20, 20)(rng);
    s.yM_mm = -27.25;
    s.zM_mm = 2.53;
    return s;
  }
  CameraPose pose() {
    std::uniform_real_distribution<> ang(-0.5, 0.5);  // about +-30 degrees
    CameraPose p;
    p.attitude = {ang(rng), std::uniform_real_distribution<>(0.02, 0.5)(rng), ang(rng)};
    p.H_mm = std::uniform_real_distribution<>(300, 2500)(rng);
    p.f_mm = std::uniform_real_distribution<>(3, 12)(rng);
    return p;
  }
  Vec2 pixel(const CameraSpec& s) {
    return {std::uniform_real_distribution<>(1, s.Nu)(rng), std::uniform_real_distribution<>(1, s.Nv)(rng)};
  }
};

TEST(CameraModelProperties, GroundThenProjectReturnsThePixel) {
  RandomScene scene;
  int checked = 0;
  for (int trial = 0; trial < 500; ++trial) {
    const CameraSpec spec = scene.spec();
    const CameraModel cam(spec, scene.pose());
    const Vec2 px = scene.pixel(spec);
    const auto g = cam.ground_point_from_pixel(px);
    if (!g) continue;  // at or above the horizon
    const auto back = cam.pixel_from_point(*g);
    ASSERT_TRUE(back.has_value());
    EXPECT_NEAR(back->x(), px.x(), 1e-7);
    EXPECT_NEAR(back->y(), px.y(), 1e-7);
    ++checked;
  }
  EXPECT_GT(checked, 250);
}

TEST(CameraModelProperties, ProjectThenGroundReturnsThePoint) {
  RandomScene scene;
  for (int trial = 0; trial < 500; ++trial) {
    const CameraModel cam(scene.spec(), scene.pose());
    // A road point somewhere in the picture: start from a pixel below the horizon.
    const auto g = cam.ground_point_from_pixel(scene.pixel(cam.spec()));
    if (!g) continue;
    const Vec3 point(g->x() * 1.01 + 5.0, g->y() - 3.0, 0.0);
    const auto px = cam.pixel_from_point(point);
    if (!px) continue;
    const auto back = cam.ground_point_from_pixel(*px);
    ASSERT_TRUE(back.has_value());
    EXPECT_LE((*back - point).norm(), 1e-9 * point.norm() + 1e-9);
  }
}

TEST(CameraModelProperties, PointsBehindTheCameraHaveNoPixel) {
  const CameraModel cam(CameraSpec{}, CameraPose{{0, 0.1, 0}, 1400, 5});
  EXPECT_FALSE(cam.pixel_from_point(Vec3(-5000, 0, 0)).has_value());
  // Just behind the lens, on the optical axis.
  EXPECT_FALSE(cam.pixel_from_point(cam.lens_centre() - cam.attitude_matrix().col(2)).has_value());
}

TEST(CameraModelProperties, PixelsAtOrAboveTheHorizonHaveNoGroundPoint) {
  const CameraModel level(CameraSpec{}, CameraPose{{0, 0, 0}, 1400, 5});
  // Level camera with no distortion: rows above the principal point look up.
  EXPECT_FALSE(level.ground_point_from_pixel(Vec2(400.5, 100)).has_value());
  EXPECT_FALSE(level.ground_point_from_pixel(Vec2(400.5, 300.5)).has_value());  // exactly the horizon
  EXPECT_TRUE(level.ground_point_from_pixel(Vec2(400.5, 301)).has_value());
}

TEST(CameraModelProperties, FocalLengthMovesTheLensAlongTheAxis) {
  const CameraSpec spec;
  const CameraModel a(spec, CameraPose{{0.1, 0.2, 0.3}, 1400, 5});
  const CameraModel b(spec, CameraPose{{0.1, 0.2, 0.3}, 1400, 6});
  EXPECT_LE(((b.lens_centre() - a.lens_centre()) - a.attitude_matrix().col(2)).norm(), 1e-12);
  EXPECT_LE((b.chip_origin() - a.chip_origin()).norm(), 1e-12);
}

// Central differences with a step scaled to the variable.
template <typename F>
Eigen::MatrixXd numeric_jacobian(F f, const Eigen::VectorXd& x0, double rel_step) {
  const Eigen::VectorXd y0 = f(x0);
  Eigen::MatrixXd j(y0.size(), x0.size());
  for (int k = 0; k < x0.size(); ++k) {
    const double h = rel_step * std::max(1.0, std::abs(x0[k]));
    Eigen::VectorXd xp = x0, xm = x0;
    xp[k] += h;
    xm[k] -= h;
    j.col(k) = (f(xp) - f(xm)) / (2 * h);
  }
  return j;
}

CameraPose pose_from(const Eigen::VectorXd& v) { return CameraPose{{v[0], v[1], v[2]}, v[3], v[4]}; }
Eigen::VectorXd vector_from(const CameraPose& p) {
  Eigen::VectorXd v(5);
  v << p.attitude.psi, p.attitude.theta, p.attitude.phi, p.H_mm, p.f_mm;
  return v;
}

TEST(CameraModelJacobians, ProjectionMatchesFiniteDifferences) {
  RandomScene scene;
  int checked = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const CameraSpec spec = scene.spec();
    const CameraPose pose = scene.pose();
    const CameraModel cam(spec, pose);
    const auto g = cam.ground_point_from_pixel(scene.pixel(spec));
    if (!g) continue;
    const Vec3 point = *g + Vec3(0, 0, 100.0);  // off the road plane too: z matters
    PointJacobian d_point;
    PoseJacobian2 d_pose;
    const auto px = cam.pixel_from_point(point, &d_point, &d_pose);
    if (!px) continue;
    auto by_point = [&](const Eigen::VectorXd& x) -> Eigen::VectorXd {
      return *cam.pixel_from_point(Vec3(x[0], x[1], x[2]));
    };
    auto by_pose = [&](const Eigen::VectorXd& x) -> Eigen::VectorXd {
      return *CameraModel(spec, pose_from(x)).pixel_from_point(point);
    };
    const Eigen::MatrixXd n_point = numeric_jacobian(by_point, Eigen::Vector3d(point), 1e-6);
    const Eigen::MatrixXd n_pose = numeric_jacobian(by_pose, vector_from(pose), 1e-7);
    EXPECT_LE((d_point - n_point).norm(), 1e-5 * (1.0 + n_point.norm())) << "d_point\n" << d_point << "\n" << n_point;
    EXPECT_LE((d_pose - n_pose).norm(), 1e-5 * (1.0 + n_pose.norm())) << "d_pose\n" << d_pose << "\n" << n_pose;
    ++checked;
  }
  EXPECT_GT(checked, 100);
}

TEST(CameraModelJacobians, CellCentreAndLensCentreMatchFiniteDifferences) {
  RandomScene scene;
  for (int trial = 0; trial < 50; ++trial) {
    const CameraSpec spec = scene.spec();
    const CameraPose pose = scene.pose();
    const Vec2 px = scene.pixel(spec);
    PoseJacobian3 d_cell, d_lens;
    const CameraModel cam(spec, pose);
    cam.cell_centre(px, &d_cell);
    cam.lens_centre(&d_lens);
    const Eigen::MatrixXd n_cell = numeric_jacobian(
        [&](const Eigen::VectorXd& x) -> Eigen::VectorXd { return CameraModel(spec, pose_from(x)).cell_centre(px); },
        vector_from(pose), 1e-7);
    const Eigen::MatrixXd n_lens = numeric_jacobian(
        [&](const Eigen::VectorXd& x) -> Eigen::VectorXd { return CameraModel(spec, pose_from(x)).lens_centre(); },
        vector_from(pose), 1e-7);
    EXPECT_LE((d_cell - n_cell).norm(), 1e-6 * (1.0 + n_cell.norm()));
    EXPECT_LE((d_lens - n_lens).norm(), 1e-6 * (1.0 + n_lens.norm()));
  }
}

TEST(CameraModel, ChipAndPixelAreInverse) {
  const CameraModel cam(CameraSpec{}, CameraPose{{}, 1400, 5});
  const Vec2 px(123.25, 456.75);
  EXPECT_LE((cam.pixel_from_chip(cam.chip_from_pixel(px)) - px).norm(), 1e-12);
  // The seed paper's cell-centre formula at the default principal point.
  const CameraSpec s;
  EXPECT_NEAR(cam.chip_from_pixel(Vec2(1, 1)).x(), -(s.U_mm - s.Uc_mm) / 2, 1e-15);
  EXPECT_NEAR(cam.chip_from_pixel(Vec2(s.Nu, s.Nv)).y(), (s.V_mm - s.Vc_mm) / 2, 1e-15);
}

}  // namespace
}  // namespace ccdlane
