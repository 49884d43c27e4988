// The vanishing point found in rendered frames whose pose is known, with the nominal
// mount passed to the finder off by up to the search's bound: the point and the attitude
// it gives against the truth; a frame with no road in it gives no point.
#include "core/detection/vanishing_point.hpp"

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "core/detection/ground_projector.hpp"
#include "tests/core/synth/rendered_road.hpp"
#include "tests/support/allocation_counter.hpp"

namespace ccdlane {
namespace {

// A straight highway: the vanishing point of the road's direction at the camera is the
// one its lines run to (on a bend the far lines run elsewhere).
Config vp_highway() {
  Config c = default_config();
  c.attitude = {0.0, 3.0, 0.0};
  c.synth.curvature_per_mm = 0.0;
  return c;
}

// Where the true pose puts the road direction (ideal pixels).
Vec2 true_point(const Config& c, const CameraPose& pose) {
  double x = 0, y = 0;
  EXPECT_TRUE(GroundProjector(c.camera, pose).vanishing_point(0.0, x, y));
  return {x, y};
}

TEST(VanishingPointFinder, FindsTheRoadsDirectionWhateverTheNominalPitchAndYaw) {
  test::RenderedRoad road(vp_highway());
  const Config& c = road.config;
  VanishingPointFinder finder(c.camera, c.detection);
  const double f_px = c.camera.pitch_u() > 0 ? c.nominal_pose().f_mm / c.camera.pitch_u() : 0.0;
  // What the point is for: a pose to start detection from, which finds lines from within
  // about 4 degrees. The bound is a quarter of that, 1 degree of view (the finder's own
  // error, measured here, is about half of it: its 2 px bins and the one-sided scatter of
  // the edges of weaving lines).
  const double tolerance_px = f_px * std::tan(deg_to_rad(1.0));
  double worst = 0.0;
  for (const double dtheta : {0.0, 5.0, -5.0})
    for (const double dpsi : {0.0, 5.0, -5.0}) {
      for (std::uint64_t k : {0u, 21u, 60u}) {
        const SynthFrame f = road.render(k);
        CameraPose nominal = c.nominal_pose();
        nominal.attitude.theta += deg_to_rad(dtheta);
        nominal.attitude.psi += deg_to_rad(dpsi);
        const VanishingPoint& vp = finder.find(road.view, nominal);
        ASSERT_TRUE(vp.found) << "frame " << k << " mount off " << dtheta << "/" << dpsi;
        const Vec2 truth = true_point(c, f.pose);
        const double miss = std::hypot(vp.x - truth.x(), vp.y - truth.y());
        worst = std::max(worst, miss);
        EXPECT_LT(miss, tolerance_px) << "frame " << k << " mount off " << dtheta << "/" << dpsi;
        const std::optional<Attitude> a = attitude_from_vanishing_point(c.camera, nominal, vp.x, vp.y);
        ASSERT_TRUE(a);
        EXPECT_NEAR(rad_to_deg(a->theta), rad_to_deg(f.pose.attitude.theta), rad_to_deg(tolerance_px / f_px));
        EXPECT_NEAR(rad_to_deg(a->psi), rad_to_deg(f.pose.attitude.psi), rad_to_deg(tolerance_px / f_px));
      }
    }
  RecordProperty("worst_miss_px", std::to_string(worst));
}

TEST(VanishingPointFinder, AttitudeFromThePointRoundTrips) {
  const Config c = vp_highway();
  for (const double theta : {-4.0, 0.0, 3.0, 9.0})
    for (const double psi : {-6.0, 0.0, 2.5}) {
      CameraPose truth = c.nominal_pose();
      truth.attitude = {deg_to_rad(psi), deg_to_rad(theta), deg_to_rad(1.0)};
      const Vec2 p = true_point(c, truth);
      CameraPose start = truth;
      start.attitude.psi = start.attitude.theta = 0.0;
      const std::optional<Attitude> a = attitude_from_vanishing_point(c.camera, start, p.x(), p.y());
      ASSERT_TRUE(a);
      EXPECT_NEAR(a->psi, truth.attitude.psi, 1e-9);
      EXPECT_NEAR(a->theta, truth.attitude.theta, 1e-9);
      EXPECT_EQ(a->phi, truth.attitude.phi) << "roll is given, not found";
    }
}

TEST(VanishingPointFinder, NoRoadNoPointAndNoAllocation) {
  const Config c = vp_highway();
  VanishingPointFinder finder(c.camera, c.detection);
  std::vector<std::uint8_t> flat(static_cast<std::size_t>(c.camera.Nu * c.camera.Nv), 90);
  const ImageView view{flat.data(), c.camera.Nu, c.camera.Nv, c.camera.Nu, PixelFormat::mono8, 8};
  test::AllocationScope scope;
  EXPECT_FALSE(finder.find(view, c.nominal_pose()).found);
  EXPECT_EQ(finder.find(view, c.nominal_pose()).edges, 0);
  EXPECT_EQ(scope.count(), 0u);
}

}  // namespace
}  // namespace ccdlane
