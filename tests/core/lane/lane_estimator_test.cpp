// The whole per-frame pipeline on rendered frames with known truth (straight, and colour
// bends solved with a shared curvature): every frame ok and
// within the solver's own sigmas of the truth, ids stable and following the road through
// a lane change, departure flagged while crossing, gyro priors and their override, the
// rank-deficient case reported, damaged frames, and no allocation per frame.
#include "core/lane/lane_estimator.hpp"

#include <cmath>
#include <initializer_list>
#include <span>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/detection/line_grouper.hpp"
#include "core/geometry/camera_model.hpp"
#include "core/geometry/road_line.hpp"
#include "core/lane/lane_support.hpp"
#include "tests/core/synth/rendered_road.hpp"
#include "tests/support/allocation_counter.hpp"

namespace ccdlane {
namespace {

Config small_camera() {
  Config c = test::small_reference_camera();
  c.detection.max_picks = 160;
  return c;
}

using Drive = test::RenderedRoad;

TEST(LaneEstimator, EveryFrameOkAndWithinTheSolversSigmasOfTheTruth) {
  Config c = small_camera();
  c.synth.noise_sigma = 1.0;
  c.synth.shadow_depth = 0.3;
  Drive d(c);
  LaneEstimator est(c.estimator_options());
  int frames = 0, within = 0;
  std::vector<int> first_ids;
  for (std::uint64_t k = 0; k < 40; k += 3) {
    const SynthFrame f = d.render(k);
    const LaneEstimate& e = est.estimate(d.view, k, f.t_ns, f.gyro);
    ASSERT_TRUE(e.ok) << "frame " << k << ": " << to_string(e.reason);
    EXPECT_EQ(e.frame, k);
    EXPECT_EQ(e.t_ns, f.t_ns);
    ASSERT_EQ(e.num_lines, 4) << "frame " << k;
    std::vector<int> ids;
    for (int j = 0; j < 4; ++j) {
      ids.push_back(e.lines[j].id);
      EXPECT_GT(e.lines[j].marks, 5);
      EXPECT_GT(e.lines[j].confidence, 0.3);
      EXPECT_LE(e.lines[j].confidence, 1.0);
      if (j > 0) {
        EXPECT_LT(e.lines[j].y0_mm, e.lines[j - 1].y0_mm);  // left to right
      }
    }
    if (first_ids.empty()) first_ids = ids;
    EXPECT_EQ(ids, first_ids) << "frame " << k;
    // Errors against the truth, in units of the solver's sigmas: 3 sigma, for the
    // attitude and the own lane's lines.
    const double zs[] = {(e.psi_deg - rad_to_deg(f.pose.attitude.psi)) / e.sigma_psi_deg,
                         (e.theta_deg - rad_to_deg(f.pose.attitude.theta)) / e.sigma_theta_deg,
                         (e.phi_deg - rad_to_deg(f.pose.attitude.phi)) / e.sigma_phi_deg,
                         (e.lines[1].y0_mm - f.y0_mm[1]) / e.lines[1].sigma_y0_mm,
                         (e.lines[2].y0_mm - f.y0_mm[2]) / e.lines[2].sigma_y0_mm};
    for (double z : zs) {
      ASSERT_TRUE(std::isfinite(z));
      within += std::abs(z) <= 3.0;
    }
    EXPECT_NEAR(e.lateral_offset_mm, f.lateral_offset_mm, 0.5 * (e.lines[1].sigma_y0_mm + e.lines[2].sigma_y0_mm) * 3);
    EXPECT_NEAR(e.lane_width_mm, 3600.0, 3 * std::hypot(e.lines[1].sigma_y0_mm, e.lines[2].sigma_y0_mm));
    EXPECT_NEAR(e.heading_deg, f.heading_deg, 3 * e.sigma_psi_deg);
    EXPECT_EQ(e.departure, Departure::none);
    EXPECT_LT(e.rms_px, 0.5);
    ++frames;
  }
  EXPECT_EQ(within, 5 * frames);
}

// How far a reported line at `y0_mm` lies from the nearest of frame f's rendered lane
// lines, at the car.
double off_lane_lines_mm(const SynthFrame& f, double y0_mm) {
  double nearest = 1e9;
  for (int t = 0; t < f.num_lines; ++t)
    nearest = std::min(nearest, std::abs(y0_mm - f.y0_mm[static_cast<std::size_t>(t)]));
  return nearest;
}

// Markings on the road that are not lane lines, on colour frames, frames `first` to
// `last` in steps of two: with solid lines every frame is ok, its offset and width within
// 3 of the solver's sigmas of the truth; with dashed lines (`dashes`: the inner ones, or
// all) some frames show one own line as a single far dash beside a marking and may have
// no lane, but more than half are ok, and no frame reports a line anywhere but on a lane
// line.
void expect_markings_leave_the_lane_alone(Config c, std::uint64_t first, std::uint64_t last,
                                          std::initializer_list<DashedLines> dashes = {DashedLines::none,
                                                                                       DashedLines::inner}) {
  c.synth.colour = true;
  for (const DashedLines dashed : dashes) {
    c.synth.dashed = dashed;
    SCOPED_TRACE(dashed == DashedLines::none    ? "solid lines"
                 : dashed == DashedLines::inner ? "dashed inner lines"
                                                : "every line dashed");
    Drive d(c, PixelFormat::rgb8);
    LaneEstimator est(c.estimator_options());
    int ok = 0, frames = 0;
    for (std::uint64_t k = first; k < last; k += 2, ++frames) {
      const SynthFrame f = d.render(k);
      const LaneEstimate& e = est.estimate(d.view, k, f.t_ns, f.gyro);
      for (int j = 0; j < e.num_lines; ++j)
        EXPECT_LT(off_lane_lines_mm(f, e.lines[j].y0_mm), 300.0)
            << "frame " << k << ": a line at y0 " << e.lines[j].y0_mm << " mm is on no lane line";
      if (dashed != DashedLines::none && !e.ok) continue;
      ASSERT_TRUE(e.ok) << "frame " << k << ": " << to_string(e.reason) << " (" << to_string(est.support_problem())
                        << ")";
      ++ok;
      int left = -1;
      for (int j = 0; j + 1 < e.num_lines; ++j)
        if (e.lines[j].y0_mm > 0 && e.lines[j + 1].y0_mm < 0) left = j;
      ASSERT_GE(left, 0);
      const double sl = e.lines[left].sigma_y0_mm, sr = e.lines[left + 1].sigma_y0_mm;
      EXPECT_NEAR(e.lateral_offset_mm, f.lateral_offset_mm, 3 * 0.5 * std::hypot(sl, sr)) << "frame " << k;
      EXPECT_NEAR(e.lane_width_mm, f.lane_width_mm, 3 * std::hypot(sl, sr)) << "frame " << k;
    }
    ::testing::Test::RecordProperty(dashed == DashedLines::none ? "solid_ok" : "dashed_ok",
                                    std::to_string(ok) + "/" + std::to_string(frames));
    if (dashed != DashedLines::none) {
      EXPECT_GT(ok, frames / 2);
    }
  }
}

// Arrows and the word STOP in the middle of every lane, every 50 m (the markings are
// neither lines nor clutter, lane_support.hpp).
TEST(LaneEstimator, ArrowsAndWordsInTheLaneLeaveTheLaneAlone) {
  Config c = small_camera();
  c.synth.road_markings = true;
  expect_markings_leave_the_lane_alone(c, 0, 60);
}

// A town's zebra crossing across the road, its stop line before it: bars 0.4 m wide
// along the road a lane mark's length, 0.6 m apart, over the lane lines too. Frames 40 to
// 100 see one come from 46 m ahead to 3 m (every 80 m; the car drives 0.83 m a frame).
TEST(LaneEstimator, AZebraCrossingLeavesTheLaneAlone) {
  Config c = small_camera();
  c.synth.crosswalks = true;
  expect_markings_leave_the_lane_alone(c, 40, 100);
}

// A crack sealed along every lane, 0.9 m right of its centre: two black bands of sealant
// 150 mm apart, the road's surface between them a strip a lane mark's width that stands
// above both its sides as paint does. On concrete and on asphalt, with the reference
// camera at its own 800x600 (at 400x300 the strip is a pixel or two wide from 10 m on, and
// nothing takes it for paint). With every line dashed, the edge lines' gaps leave the
// strip alone beside the lane: the strip is told by the road beyond its beads, as bright
// as it (LaneDetector::between_beads; without it the 90 frames on concrete reported a
// line on the strip 15 times).
TEST(LaneEstimator, ASealedCrackAlongTheLaneLeavesTheLaneAlone) {
  for (const RoadSurface surface : {RoadSurface::concrete, RoadSurface::asphalt}) {
    SCOPED_TRACE(surface == RoadSurface::concrete ? "concrete" : "asphalt");
    Config c = default_config();
    c.synth.sealed_cracks = true;
    c.synth.surface = surface;
    expect_markings_leave_the_lane_alone(c, 0, 60);
    expect_markings_leave_the_lane_alone(c, 0, 180, {DashedLines::all});
  }
}

// Contrast markings on pale concrete: every line's white paint between black borders 90
// mm wide (some US states' freeways), at the reference camera's 800x600. The borders are
// steps beside the paint's edges that a bar is otherwise held for (MarkScanner): without
// between_black_borders no frame had a lane. Far away, paint and borders blur into one
// dark band: a lane of single dashes (every line dashed) is found on about two frames in
// three, and that is not asked here.
TEST(LaneEstimator, ContrastMarkingsOnPaleConcreteAreLanes) {
  Config c = default_config();
  c.synth.surface = RoadSurface::concrete;
  c.synth.contrast_borders_mm = 90.0;
  expect_markings_leave_the_lane_alone(c, 0, 60);
}

// At night, with the road lit by the car's low beams alone (the near road as by day, 30 m
// ahead a sixteenth of it, past their cut-off near black) and a sensor at night's gain
// (noise 3 levels): the paint is seen to 30-40 m, and the lane is what it is by day.
TEST(LaneEstimator, ANightsRoadInTheHeadlightsIsALane) {
  Config c = small_camera();
  c.synth.night = true;
  c.synth.noise_sigma = 3.0;
  expect_markings_leave_the_lane_alone(c, 0, 60, {DashedLines::none, DashedLines::inner, DashedLines::all});
}

// Six cars: one ahead in the own lane, one beside the car on each side (3-9 m ahead, its
// side in full view over the next line's near dashes), three more farther on; their
// bodies' edges, dark underbodies and tail lights among the marks, the lines behind them
// hidden. By day and at night: the lane is what it is without them.
TEST(LaneEstimator, CarsAheadLeaveTheLaneAlone) {
  Config c = small_camera();
  c.synth.cars = 6;
  expect_markings_leave_the_lane_alone(c, 0, 60, {DashedLines::none, DashedLines::inner, DashedLines::all});
  c.synth.night = true;
  c.synth.noise_sigma = 3.0;
  expect_markings_leave_the_lane_alone(c, 0, 60);
}

// Six cars on a 330 m bend of concrete with tree shadows, at the reference camera's
// 800x600, tracked frame after frame. Where a car beside hides an own line's dashes, the
// tree shadows' borders made the line: with seed 4 on frames 30 and 31, 720 mm outside
// the right one at the car, the yaw 3.5 degrees off to match (the tracked line's
// continuation); with seed 3 on frame 29, 550 mm out and 1.7 degrees; with seed 1 on
// frame 36, 430 mm out, the yaw turned 2.8 degrees in the frame. Each is more than a
// vehicle moves sideways or turns in a frame's time (own_line_jumped, yaw_jumped): the
// frame looks afresh, as a search does, and finds the lane or has none. Checked on the
// frames with a lane, what a departure warning takes: the own lines on their lane lines,
// the yaw within 2 degrees of the truth (hidden lines still leave a frame of seed 1 1.5
// degrees off, reached a step at a time: docs/real-roads.md, open; the lines beyond the
// own lane, seen only between the cars 25-45 m ahead, are a long extrapolation at the
// car and not held here).
TEST(LaneEstimator, ALaneThatJumpsFromTheTrackedOneIsNotTaken) {
  for (const unsigned seed : {1u, 3u, 4u}) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    Config c = default_config();
    c.synth.seed = seed;
    c.synth.colour = true;
    c.synth.surface = RoadSurface::concrete;
    c.synth.hard_shadows = true;
    c.synth.cars = 6;
    c.synth.curvature_per_mm = 1.0 / (2.0 * 330.0e3);
    Drive d(c, PixelFormat::rgb8);
    LaneEstimator est(c.estimator_options());
    int ok = 0;
    for (std::uint64_t k = 0; k < 40; ++k) {
      const SynthFrame f = d.render(k);
      const LaneEstimate& e = est.estimate(d.view, k, f.t_ns, f.gyro);
      if (!e.ok) continue;
      ++ok;
      EXPECT_NEAR(e.psi_deg, rad_to_deg(f.pose.attitude.psi), 2.0) << "frame " << k;
      const std::span<const EstimatedLine> lines(e.lines.data(), static_cast<std::size_t>(e.num_lines));
      const OwnLaneLines own = own_lane_lines(lines);
      ASSERT_TRUE(own.left >= 0 && own.right >= 0) << "frame " << k;
      for (const int j : {own.left, own.right}) {
        const double y0 = e.lines[static_cast<std::size_t>(j)].y0_mm;
        EXPECT_LT(off_lane_lines_mm(f, y0), 300.0)
            << "frame " << k << ": an own line at y0 " << y0 << " mm is on no lane line";
      }
    }
    // Frames whose own line a car hides may have no lane; most have one.
    EXPECT_GE(ok, 35);
  }
}

// Bends of radius 300 to 2000 m, both ways, on colour frames of a concrete road with a
// yellow left edge line, solved with one shared curvature ([solver] line_model = "curved"):
// yaw, pitch, the lateral offset and the curvature within 3 of the solver's own sigmas.
// With solid lines, and with the inner lines dashed (3 m dashes, 9 m gaps): every frame
// must then be ok, because every frame shows a whole dash of each own-lane line in the
// rows a single dash is taken from (checked below from the camera model), and detection
// takes a line from one dash when it is parallel to the road's other lines.
TEST(LaneEstimator, CurvedRoadsWithinTheSolversSigmasOfTheTruth) {
  int frames = 0, within = 0, checks = 0;
  double worst_z[4] = {0, 0, 0, 0};
  for (const DashedLines dashed : {DashedLines::none, DashedLines::inner})
    for (const double radius_m : {300.0, -600.0, 1000.0, -2000.0}) {
      Config c = small_camera();
      c.solver.line_model = LineModel::shared_curvature;
      c.synth.curvature_per_mm = 1.0 / (2.0 * radius_m * 1000.0);
      c.synth.dashed = dashed;
      if (dashed != DashedLines::none) {
        // Dashes repeat every 12 m: the 15 m from the nearest row searched always hold one
        // whole dash, at worst [min_range + 12 m - 3 m, min_range + 12 m] ahead. There it
        // must cover at least the rows a single-dash line needs (GroupingParams::
        // min_dash_marks, one candidate per scanned row; rows there are not thinned: marks
        // are under 6 px wide).
        const CameraModel cam(c.camera, c.nominal_pose());
        const double period = c.synth.dash_length_mm + c.synth.dash_gap_mm;
        const double far_end = c.detection.min_range_mm + period;
        const auto near_px = cam.pixel_from_point(Vec3(far_end - c.synth.dash_length_mm, 1800.0, 0.0));
        const auto far_px = cam.pixel_from_point(Vec3(far_end, 1800.0, 0.0));
        ASSERT_TRUE(near_px && far_px);
        ASSERT_GE(std::floor(near_px->y() - far_px->y()), GroupingParams{}.min_dash_marks + 1)
            << "the worst-placed whole dash spans too few rows for this test's premise";
      }
      c.synth.colour = c.synth.yellow_left_edge = true;
      c.synth.surface = RoadSurface::concrete;
      Drive d(c, PixelFormat::rgb8);
      LaneEstimator est(c.estimator_options());
      for (std::uint64_t k = 0; k < 30; k += 6) {
        const SynthFrame f = d.render(k);
        const LaneEstimate& e = est.estimate(d.view, k, f.t_ns, f.gyro);
        ASSERT_TRUE(e.ok) << "R " << radius_m << " dashed " << static_cast<int>(dashed) << " frame " << k << ": "
                          << to_string(e.reason) << " (" << to_string(est.support_problem()) << ")";
        ASSERT_GE(e.num_lines, 3) << "R " << radius_m << " frame " << k;
        ASSERT_NE(est.solution(), nullptr);
        const double sigma_c = est.solution()->sigma.c_per_mm[0];
        // The own lane: the lines either side of the vehicle.
        int left = -1;
        for (int j = 0; j + 1 < e.num_lines; ++j)
          if (e.lines[j].y0_mm > 0 && e.lines[j + 1].y0_mm < 0) left = j;
        ASSERT_GE(left, 0);
        const double sigma_offset = 0.5 * std::hypot(e.lines[left].sigma_y0_mm, e.lines[left + 1].sigma_y0_mm);
        const double zs[] = {(e.psi_deg - rad_to_deg(f.pose.attitude.psi)) / e.sigma_psi_deg,
                             (e.theta_deg - rad_to_deg(f.pose.attitude.theta)) / e.sigma_theta_deg,
                             (e.lateral_offset_mm - f.lateral_offset_mm) / sigma_offset,
                             (e.lines[0].c_per_mm - f.c_per_mm) / sigma_c};
        for (int i = 0; i < 4; ++i) {
          ASSERT_TRUE(std::isfinite(zs[i])) << i;
          worst_z[i] = std::max(worst_z[i], std::abs(zs[i]));
          within += std::abs(zs[i]) <= 3.0;
          ++checks;
        }
        for (int j = 1; j < e.num_lines; ++j) EXPECT_EQ(e.lines[j].c_per_mm, e.lines[0].c_per_mm);
        ++frames;
      }
    }
  EXPECT_EQ(within, checks) << "worst |error| / sigma: yaw " << worst_z[0] << ", pitch " << worst_z[1] << ", offset "
                            << worst_z[2] << ", curvature " << worst_z[3];
  RecordProperty("worst_z_yaw_pitch_offset_c", std::to_string(worst_z[0]) + " " + std::to_string(worst_z[1]) + " " +
                                                   std::to_string(worst_z[2]) + " " + std::to_string(worst_z[3]));
  EXPECT_EQ(frames, 40);
}

// A three-lane road with dashed inner lines bending at this radius (m, + left), driven at
// 36 km/h, seen by the reference camera (800x600) and solved with a shared curvature.
Config bend(double radius_m) {
  Config c = default_config();
  c.solver.line_model = LineModel::shared_curvature;
  c.synth.curvature_per_mm = 1.0 / (2.0 * radius_m * 1000.0);
  c.synth.dashed = DashedLines::inner;
  c.synth.speed_mps = 10.0;
  return c;
}

// Of an ok estimate on a synthetic bend: its lateral offset and lane width each within 3
// of the solver's sigmas of the truth (`within` of `checks`). False when the own lane's
// two lines are not among its lines.
bool tally_truth(const LaneEstimate& e, const SynthFrame& f, const Config& c, int& within, int& checks) {
  int left = -1;
  for (int j = 0; j + 1 < e.num_lines; ++j)
    if (e.lines[j].y0_mm > 0 && e.lines[j + 1].y0_mm < 0) left = j;
  if (left < 0) return false;
  const double sigma_width = std::hypot(e.lines[left].sigma_y0_mm, e.lines[left + 1].sigma_y0_mm);
  within += std::abs(e.lateral_offset_mm - f.lateral_offset_mm) <= 3.0 * 0.5 * sigma_width;
  within += std::abs(e.lane_width_mm - c.synth.lane_width_mm) <= 3.0 * sigma_width;
  checks += 2;
  return true;
}

// Sharp bends, 120 m radius either way (a ramp, a city street), driven at 36 km/h (0.8
// m/s^2 sideways), on a three-lane road with dashed inner lines, seen by the reference
// camera (800x600): every frame ok, with the lane's width and the offset within 3 of the
// solver's sigmas of the truth. On such a bend the own lane's dashed lines leave the view
// after a dash or two (both may be single dashes beside the solid edge lines), and a
// mark 12 m ahead runs 5.7 degrees off the straight road's direction, which near the
// horizon turns its way in the picture by tens of degrees: while tracking a lane,
// detection judges each bar against the point of the road's tangent at its distance.
// (Before both, replayed at daemon/ccdlane.toml's camera: 90 of these 180 frames ok;
// docs/real-roads.md. This test itself was not run on the code before them.)
TEST(LaneEstimator, SharpBendsAreFoundAtEveryFrame) {
  int frames = 0, ok = 0, within = 0, checks = 0;
  for (const double radius_m : {120.0, -120.0}) {
    Config c = bend(radius_m);
    c.vehicle.speed_kmh = 36.0;
    Drive d(c);
    LaneEstimator est(c.estimator_options());
    for (std::uint64_t k = 0; k < 90; ++k) {
      const SynthFrame f = d.render(k);
      const LaneEstimate& e = est.estimate(d.view, k, f.t_ns, f.gyro);
      ++frames;
      if (!e.ok) {
        ADD_FAILURE() << "R " << radius_m << " frame " << k << ": " << to_string(e.reason) << " ("
                      << to_string(est.support_problem()) << ")";
        continue;
      }
      ++ok;
      ASSERT_TRUE(tally_truth(e, f, c, within, checks)) << "R " << radius_m << " frame " << k;
    }
  }
  EXPECT_EQ(ok, frames);
  EXPECT_EQ(within, checks);
}

// A still of a sharp bend (a city street, a ramp; replay --stills, a daemon starting on
// one): 50 and 60 m radius either way, each frame alone. Beyond 10-20 m such a bend's
// marks run tens of degrees off the way to the straight road's point, and the search's
// look again refused them; a search that finds no lane looks again along the bend its
// first solve showed (LaneEstimator::search). Before: 10 of 30 stills ok at 60 m, 6 of 30
// at 50 m. The lanes found have their true width and offset (3 sigma, as above).
TEST(LaneEstimator, StillsOfSharpBendsAreLanes) {
  int stills = 0, ok = 0, within = 0, checks = 0;
  for (const double radius_m : {60.0, -60.0, 50.0, -50.0}) {
    const Config c = bend(radius_m);
    Drive d(c);
    VehicleInputs speed;
    speed.speed_mps = c.synth.speed_mps;
    for (std::uint64_t k = 0; k < 20; ++k) {
      const SynthFrame f = d.render(k);
      LaneEstimator est(c.estimator_options());
      const LaneEstimate& e = est.estimate(d.view, k, f.t_ns, f.gyro, speed);
      ++stills;
      if (!e.ok) continue;
      ++ok;
      ASSERT_TRUE(tally_truth(e, f, c, within, checks)) << "R " << radius_m << " still " << k;
    }
  }
  // 74 of 80 when this was written (the old search: about 22). The floor is that less two
  // and a half binomial sigmas of its 7 % of misses (2.4 stills).
  RecordProperty("stills_ok", ok);
  EXPECT_GE(ok, 68) << ok << " of " << stills << " stills ok";
  EXPECT_EQ(within, checks);
}

// A drive replayed from a video has no speed, and the configured one ([vehicle]
// speed_kmh, 72 km/h by default) would refuse every bend sharper than 100 m as too sharp
// to follow (its lateral acceleration), though a car takes it at 36 km/h. Without a speed
// a lane's motion is judged at the speed its bend is taken at (judged_speed_mps): on 80 m
// bends either way, driven at 36 km/h, a frame is ok without a speed input exactly when
// it is ok with the speed measured, and the same then.
TEST(LaneEstimator, WithoutASpeedABendIsJudgedAtTheSpeedItIsTakenAt) {
  int ok = 0;
  for (const double radius_m : {80.0, -80.0}) {
    const Config c = bend(radius_m);
    const double configured_mps = c.vehicle.configured_speed_mps();
    ASSERT_GT(configured_mps * configured_mps / std::abs(radius_m), kMaxLateralAccelerationMps2);
    Drive d(c);
    LaneEstimator measured(c.estimator_options()), unmeasured(c.estimator_options());
    VehicleInputs speed;
    speed.speed_mps = c.synth.speed_mps;
    for (std::uint64_t k = 0; k < 60; ++k) {
      const SynthFrame f = d.render(k);
      const LaneEstimate with_speed = measured.estimate(d.view, k, f.t_ns, f.gyro, speed);
      const LaneEstimate& e = unmeasured.estimate(d.view, k, f.t_ns, f.gyro);
      ASSERT_EQ(e.ok, with_speed.ok) << "R " << radius_m << " frame " << k << ": " << to_string(e.reason) << " ("
                                     << to_string(unmeasured.support_problem()) << ")";
      if (!e.ok) continue;
      ++ok;
      EXPECT_EQ(e.lane_width_mm, with_speed.lane_width_mm) << "frame " << k;
      EXPECT_EQ(e.lateral_offset_mm, with_speed.lateral_offset_mm) << "frame " << k;
    }
  }
  // And nearly every frame is a lane (116 of the 120 when this was written): the frames
  // compared are not just failures alike.
  EXPECT_GE(ok, 110);
}

TEST(LaneEstimator, IdsFollowTheRoadThroughALaneChangeAndDepartureIsFlagged) {
  Config c = small_camera();
  c.synth.lane_change_at_s = 1.0;
  c.synth.lane_change_s = 3.0;
  c.synth.weave_mm = 0;
  Drive d(c);
  LaneEstimator est(c.estimator_options());
  int id_of_crossed = -1;  // the line between lanes 1 and 2 (road line 2)
  bool right_departure = false, left_departure = false;
  for (std::uint64_t k = 0; k <= 150; k += 5) {
    const SynthFrame f = d.render(k);
    const LaneEstimate& e = est.estimate(d.view, k, f.t_ns, f.gyro);
    ASSERT_GE(e.num_lines, 2) << "frame " << k;
    for (int j = 0; j < e.num_lines; ++j) {
      if (std::abs(e.lines[j].y0_mm - f.y0_mm[2]) > 300) continue;
      if (id_of_crossed < 0) id_of_crossed = e.lines[j].id;
      EXPECT_EQ(e.lines[j].id, id_of_crossed) << "frame " << k;
    }
    if (e.ok) {
      right_departure = right_departure || e.departure == Departure::right;
      left_departure = left_departure || e.departure == Departure::left;
      // Before the change nothing; crossing: right while the line is still right of the
      // vehicle, left once it has passed under.
      if (f.t_ns < 900'000'000) {
        EXPECT_EQ(e.departure, Departure::none) << "frame " << k;
      }
      if (e.departure == Departure::right) {
        EXPECT_LT(f.y0_mm[2], 0.0);
      }
    }
  }
  EXPECT_GE(id_of_crossed, 0);
  EXPECT_TRUE(right_departure);
  EXPECT_TRUE(left_departure);
}

TEST(LaneEstimator, GyroPriorsAndTheirOverride) {
  Config c = small_camera();
  Drive d(c);
  const SynthFrame f = d.render(3);
  {  // No gyro, no roll prior: roll about the lane is not determined, and said so.
    LaneEstimator est(c.estimator_options());
    const LaneEstimate& e = est.estimate(d.view, 3, f.t_ns, std::nullopt);
    EXPECT_FALSE(e.ok);
    EXPECT_EQ(e.reason, EstimateFailure::rank_deficient);
  }
  {  // The gyro's roll makes it determined, to about the gyro's sigma.
    LaneEstimator est(c.estimator_options());
    const LaneEstimate& e = est.estimate(d.view, 3, f.t_ns, f.gyro);
    ASSERT_TRUE(e.ok) << to_string(e.reason);
    EXPECT_NEAR(e.sigma_phi_deg, c.gyro.sigma_deg, 0.05);
  }
  {  // A [prior] on roll overrides the gyro's.
    Config strict = c;
    strict.prior.phi_deg = Prior{rad_to_deg(f.pose.attitude.phi) + 0.8, 0.01};
    LaneEstimator est(strict.estimator_options());
    const LaneEstimate& e = est.estimate(d.view, 3, f.t_ns, f.gyro);
    ASSERT_TRUE(e.ok) << to_string(e.reason);
    EXPECT_NEAR(e.phi_deg, rad_to_deg(f.pose.attitude.phi) + 0.8, 0.05);
    EXPECT_LT(e.sigma_phi_deg, 0.011);
  }
}

TEST(LaneEstimator, DamagedAndEmptyFramesAndRecovery) {
  Config c = small_camera();
  Drive d(c);
  LaneEstimator est(c.estimator_options());
  SynthFrame f = d.render(0);
  ASSERT_TRUE(est.estimate(d.view, 0, f.t_ns, f.gyro).ok);
  const int left_id = est.estimate(d.view, 0, f.t_ns, f.gyro).lines[1].id;
  const LaneEstimate& damaged = est.no_frame(1, 33);
  EXPECT_FALSE(damaged.ok);
  EXPECT_EQ(damaged.reason, EstimateFailure::no_frame);
  EXPECT_EQ(damaged.frame, 1u);
  std::fill(d.px.begin(), d.px.end(), 90);  // nothing to see
  EXPECT_EQ(est.estimate(d.view, 2, 66, f.gyro).reason, EstimateFailure::too_few_marks);
  f = d.render(3);
  const LaneEstimate& back = est.estimate(d.view, 3, f.t_ns, f.gyro);
  ASSERT_TRUE(back.ok);
  EXPECT_EQ(back.lines[1].id, left_id);  // the lines coasted over the gap
  EXPECT_EQ(est.estimate(ImageView{}, 4, 0, f.gyro).reason, EstimateFailure::too_few_marks);
}

// A camera mounted 1.5 degrees off the configured yaw shows that much heading bias; the
// online refinement's correction (here one learned before) moves the reference the
// heading is measured from, and the bias goes (3 of the solver's sigmas). An
// uncalibrated mount makes LDW unavailable.
TEST(LaneEstimator, AMountCorrectionMovesTheHeadingReferenceAndUncalibratedStopsLdw) {
  Config truth = small_camera();
  truth.attitude.psi_deg += 1.5;
  Drive d(truth);
  Config configured = small_camera();
  LaneEstimator est(configured.estimator_options());
  const SynthFrame f0 = d.render(0);
  const LaneEstimate& off = est.estimate(d.view, 0, f0.t_ns, f0.gyro);
  ASSERT_TRUE(off.ok);
  EXPECT_NEAR(off.heading_deg - f0.heading_deg, 1.5, 3 * off.sigma_psi_deg) << "the mis-mount is a heading bias";
  LaneEstimatorOptions learned = configured.estimator_options();
  learned.online_mount = configured.online_mount_options();
  learned.learned_mount = calibration::LearnedMount{{1.5, 0.0}, {1.5, 0.0}, {}, 0};
  LaneEstimator with_correction(learned);
  with_correction.estimate(d.view, 0, f0.t_ns, f0.gyro);
  VehicleInputs vehicle;
  vehicle.calibrated = false;
  const SynthFrame f1 = d.render(1);
  const LaneEstimate& corrected = with_correction.estimate(d.view, 1, f1.t_ns, f1.gyro, vehicle);
  ASSERT_TRUE(corrected.ok);
  EXPECT_NEAR(corrected.heading_deg, f1.heading_deg, 3 * corrected.sigma_psi_deg);
  EXPECT_FALSE(corrected.ldw.available);
  EXPECT_EQ(corrected.ldw.reason, ldw::Availability::not_calibrated);
}

// A mount known only roughly: configured 5 degrees off in pitch or in yaw. The first frame
// searches (the picture's vanishing point, then pitch steps) and is ok; the frames after
// it track; the solved pitch is the true one within the solver's sigmas, and the heading,
// measured from the mount the first second of solves shows, is the truth's within the
// sigmas plus what the vehicle's heading averaged over that second (the drive weaves).
TEST(LaneEstimator, AMountFiveDegreesOffIsFoundFromThePicture) {
  for (const AttitudeDeg off : {AttitudeDeg{0.0, 5.0, 0.0}, AttitudeDeg{0.0, -5.0, 0.0}, AttitudeDeg{5.0, 0.0, 0.0},
                                AttitudeDeg{-5.0, 0.0, 0.0}}) {
    const Config truth = small_camera();
    Drive d(truth);
    Config configured = truth;
    configured.attitude.psi_deg += off.psi_deg;
    configured.attitude.theta_deg += off.theta_deg;
    LaneEstimator est(configured.estimator_options());
    const int n = MountRefinement::kMountAcquisitionFrames;
    double heading_sum = 0.0, pitch_sum = 0.0, sigma_psi = 0.0, sigma_theta = 0.0;
    for (std::uint64_t k = 0; k < 40; ++k) {
      const SynthFrame f = d.render(k);
      const LaneEstimate& e = est.estimate(d.view, k, f.t_ns, f.gyro);
      ASSERT_TRUE(e.ok) << "mount off " << off.psi_deg << "/" << off.theta_deg << " frame " << k << ": "
                        << to_string(e.reason);
      EXPECT_EQ(e.state, k == 0 ? EstimatorState::searching : EstimatorState::tracking);
      EXPECT_NEAR(e.theta_deg, rad_to_deg(f.pose.attitude.theta), 3 * e.sigma_theta_deg) << "frame " << k;
      EXPECT_NEAR(e.lane_width_mm, 3600.0, 3 * std::hypot(e.lines[1].sigma_y0_mm, e.lines[2].sigma_y0_mm));
      sigma_psi = e.sigma_psi_deg, sigma_theta = e.sigma_theta_deg;
      if (k < static_cast<std::uint64_t>(n)) {
        heading_sum += f.heading_deg;
        pitch_sum += rad_to_deg(f.pose.attitude.theta);
        continue;
      }
      // This frame's yaw error and the acquired mean's (n frames: sigma / sqrt(n)).
      EXPECT_NEAR(e.heading_deg, f.heading_deg - heading_sum / n, 3 * e.sigma_psi_deg * std::sqrt(1.0 + 1.0 / n))
          << "frame " << k;
    }
    // The mount is the mean of the first n solves: the true mount plus the vehicle's mean
    // heading and pitch over them, within the mean's sigma.
    EXPECT_NEAR(rad_to_deg(est.mount().psi), truth.attitude.psi_deg + heading_sum / n, 3 * sigma_psi / std::sqrt(n));
    EXPECT_NEAR(rad_to_deg(est.mount().theta), pitch_sum / n, 3 * sigma_theta / std::sqrt(n));
  }
}

// Online refinement from the same rough mount: configured 5 degrees off in yaw and in
// pitch, with [calibration] online on its defaults but for the frames it needs (50 here,
// not 900: the rendered drive is short). The start replaces the mount; the online
// estimate, which is measured from the configured mount and bounded there, reaches the
// truth's offset within its own sigma and the drive's mean heading over the frames used,
// is calibrated (not out of its bounds), and lane departure warning stays available.
TEST(LaneEstimator, OnlineRefinementFromAMountFiveDegreesOffConverges) {
  const Config truth = small_camera();
  Drive d(truth);
  Config configured = truth;
  configured.attitude.psi_deg -= 5.0;
  configured.attitude.theta_deg += 5.0;
  configured.calibration.online = true;
  configured.calibration.frames_needed = 50;
  LaneEstimatorOptions options = configured.estimator_options();
  options.online_mount = configured.online_mount_options();
  LaneEstimator est(options);
  double heading_sum = 0.0, pitch_sum = 0.0;
  int used = 0;
  for (std::uint64_t k = 0; k < 60; ++k) {
    const SynthFrame f = d.render(k);
    const LaneEstimate& e = est.estimate(d.view, k, f.t_ns, f.gyro);
    ASSERT_TRUE(e.ok) << "frame " << k << ": " << to_string(e.reason);
    if (k + 1 == 60) {
      EXPECT_TRUE(e.ldw.available) << ldw::to_string(e.ldw.reason);
    }
    if (!est.mount_refinement().used) continue;
    ++used;
    heading_sum += f.heading_deg;
    pitch_sum += rad_to_deg(f.pose.attitude.theta) - truth.attitude.theta_deg;
  }
  const calibration::OnlineMountStatus& s = est.mount_refinement().status;
  EXPECT_EQ(s.state, calibration::OnlineMountState::calibrated);
  ASSERT_GE(used, 50);
  EXPECT_NEAR(s.estimate.psi_deg, 5.0 + heading_sum / used, 3 * s.sigma.psi_deg);
  EXPECT_NEAR(s.estimate.theta_deg, -5.0 + pitch_sum / used, 3 * s.sigma.theta_deg);
}

// The small camera configured `factor` times its height, with a lane-width prior of the
// rendered lanes' width.
Config height_off(const Config& truth, double factor) {
  Config configured = truth;
  configured.H_mm *= factor;
  configured.prior.lane_width_mm = Prior{3600.0, 300.0};
  return configured;
}

// A height known only roughly: configured a quarter off, with a lane-width prior. Each
// frame alone (a still: reset before it) searches; the first solve's lane is a quarter
// too narrow or too wide, and the look again is from the height the prior's width says.
// On this road (lanes of the prior's mean width) that is the true height, within what
// the solve's width is known to; the lines and width are reported at it.
TEST(LaneEstimator, AHeightAQuarterOffIsTakenFromTheLaneWidthOnEachStill) {
  for (const double factor : {0.75, 1.25}) {
    const Config truth = small_camera();
    Drive d(truth);
    LaneEstimator est(height_off(truth, factor).estimator_options());
    for (std::uint64_t k = 0; k < 30; k += 3) {
      est.reset();
      const SynthFrame f = d.render(k);
      const LaneEstimate& e = est.estimate(d.view, k, f.t_ns, f.gyro);
      ASSERT_TRUE(e.ok) << "height x" << factor << " frame " << k << ": " << to_string(e.reason);
      EXPECT_EQ(e.state, EstimatorState::searching);
      const double sigma_width = std::hypot(e.lines[1].sigma_y0_mm, e.lines[2].sigma_y0_mm);
      EXPECT_NEAR(e.H_mm, truth.H_mm, 3.0 * sigma_width / 3600.0 * truth.H_mm) << "x" << factor << " frame " << k;
      EXPECT_NEAR(e.lane_width_mm, 3600.0, 3.0 * sigma_width) << "x" << factor << " frame " << k;
    }
  }
}

// The height a cold start's first solve says its lane's width gives is taken when it is
// one the search itself tries about the mount's (up to kSearchHeightStep squared either
// way), wherever the solve's own pose was: from the highest step, a lane 1.38 times a
// lane's width says 1.23 times the mount's height (TuSimple still 7); 0.67 times says
// 2.5 times, which no search tries. The bounds hold at both ends.
TEST(LaneEstimator, AHeightIsTakenFromALanesWidthAmongTheHeightsTheSearchTries) {
  const double mount = 1300.0, lane = 3660.0;
  const double span = LaneEstimator::kSearchHeightStep * LaneEstimator::kSearchHeightStep;
  const double top = mount * span;
  EXPECT_DOUBLE_EQ(LaneEstimator::height_scale_for(top, mount, 1.38 * lane, lane), 1.0 / 1.38);
  EXPECT_EQ(LaneEstimator::height_scale_for(top, mount, 0.67 * lane, lane), 1.0);
  // From the mount's own height: a lane 1.6 times a lane's width is seen from 0.625 of it.
  EXPECT_DOUBLE_EQ(LaneEstimator::height_scale_for(mount, mount, 1.6 * lane, lane), 1.0 / 1.6);
  for (const double inside : {0.999, 1.001}) {
    const bool within = inside < 1.0;
    EXPECT_EQ(LaneEstimator::height_scale_for(mount, mount, lane / (span * inside), lane) != 1.0, within) << inside;
    EXPECT_EQ(LaneEstimator::height_scale_for(mount, mount, lane * span * inside, lane) != 1.0, within) << inside;
  }
}

// A search's lane and the height it says: a lane's width at the height it was looked from
// is a lane there; of another width, one at another height; looked at again from the
// height its width said, one at another height only when it is a lane's width there.
TEST(LaneEstimator, ALaneLookedAtAgainFromTheHeightItsWidthSaidMustBeALanesWidthThere) {
  using H = LaneEstimator::LaneHeight;
  EXPECT_EQ(LaneEstimator::lane_height(false, true), H::as_looked_from);
  EXPECT_EQ(LaneEstimator::lane_height(false, false), H::another);
  EXPECT_EQ(LaneEstimator::lane_height(true, true), H::another);
  EXPECT_EQ(LaneEstimator::lane_height(true, false), H::neither);
}

// The same height a quarter off on a drive: the first frame searches and looks again from
// the height the width says; after kMountAcquisitionFrames frames the mount's height is
// taken from their mean width, and the tracked lines go on at it, rescaled (the frame
// after is tracked, its lines keep their ids), where they were searched for afresh.
TEST(LaneEstimator, AHeightAQuarterOffIsAcquiredOnADriveAndTheLinesGoOn) {
  for (const double factor : {0.75, 1.25}) {
    const Config truth = small_camera();
    Drive d(truth);
    LaneEstimator est(height_off(truth, factor).estimator_options());
    std::vector<int> ids;
    for (std::uint64_t k = 0; k < 2 * MountRefinement::kMountAcquisitionFrames; ++k) {
      const SynthFrame f = d.render(k);
      const LaneEstimate& e = est.estimate(d.view, k, f.t_ns, f.gyro);
      ASSERT_TRUE(e.ok) << "height x" << factor << " frame " << k << ": " << to_string(e.reason);
      EXPECT_EQ(e.state, k == 0 ? EstimatorState::searching : EstimatorState::tracking) << "x" << factor << " " << k;
      // Until then the search's height may be a step's (kSearchHeightStep) whose lane is
      // within the prior's trust of its mean: the road seen is the true one scaled by
      // the height's error. From then on, the height is the one the widths say.
      const double sigma_width = std::hypot(e.lines[1].sigma_y0_mm, e.lines[2].sigma_y0_mm);
      const double scale = k < MountRefinement::kMountAcquisitionFrames ? truth.H_mm / e.H_mm : 1.0;
      EXPECT_NEAR(e.lane_width_mm * scale, 3600.0, 3.0 * sigma_width * scale) << "x" << factor << " frame " << k;
      if (k >= MountRefinement::kMountAcquisitionFrames) {
        EXPECT_NEAR(e.H_mm, truth.H_mm, 3.0 * sigma_width / 3600.0 * truth.H_mm) << "x" << factor << " frame " << k;
      }
      std::vector<int> now;
      for (int j = 0; j < e.num_lines; ++j) now.push_back(e.lines[static_cast<std::size_t>(j)].id);
      if (k > 0) {
        EXPECT_EQ(now, ids) << "x" << factor << " frame " << k;
      }
      ids = now;
    }
  }
}

// The same with the own lane's lines dashed and the next lanes' solid, configured up to a
// third too low: lanes look a third narrower, too narrow for two lines (a dash and the
// solid line beyond) to be taken as a lane's, and dashes give few marks at a detection
// pose that low. The search also starts from the height a step higher
// (kSearchHeightStep), and takes the lane it finds there: the true one, at a height
// within a tenth of the truth's (its own lane is the prior's width at it). Configured at
// a bit over half its height, the camera sees two lanes as one of a lane's width (7.2 m
// at 0.55 of the height reads 4 m), bounded by the lines either side of them, with the
// dashed line between them inside, and its own lane too narrow (2 m) to rescale the
// height from: the search prefers the lane from the height a step higher, where no line
// runs inside it. Configured at half or twice the truth, the heights two steps either
// way (kSearchHeightStep squared) find it.
TEST(LaneEstimator, ASearchFindsTheOwnLaneBetweenDashesFromAHeightFarOff) {
  for (const double factor : {0.5, 0.55, 0.68, 0.75, 2.0}) {
    Config truth = small_camera();
    truth.synth.dashed = DashedLines::inner;
    Drive d(truth);
    LaneEstimator est(height_off(truth, factor).estimator_options());
    int ok = 0;
    for (std::uint64_t k = 0; k < 30; k += 3) {
      est.reset();
      const SynthFrame f = d.render(k);
      const LaneEstimate& e = est.estimate(d.view, k, f.t_ns, f.gyro);
      if (!e.ok) continue;  // a dash may be between the searched range's ends
      ++ok;
      const double sigma_width = std::hypot(e.lines[1].sigma_y0_mm, e.lines[2].sigma_y0_mm);
      const double scale = truth.H_mm / e.H_mm;
      EXPECT_NEAR(e.lane_width_mm * scale, 3600.0, 3.0 * sigma_width + 0.1 * 3600.0)
          << "x" << factor << " frame " << k << ": the lane is at the height it was found at";
      EXPECT_NEAR(e.lateral_offset_mm * scale, f.lateral_offset_mm, 300.0) << "x" << factor << " frame " << k;
    }
    EXPECT_GE(ok, 5) << "x" << factor;
  }
}

// A still with no lane: the own lane's left line in full, of its right line a 4 m piece
// (too short for a line's support, and paint: no lane beside a single full line), every
// other line painted over. The estimate is no lane, and it reports the lines that have a
// line's support on their own: the left line, not the piece.
// Frame k of a straight drive with every line painted over but the own lane's left line
// and, when `right_piece`, a 4 m piece of its right line 8-12 m ahead.
SynthFrame render_left_line(Drive& d, const Config& c, std::uint64_t k, bool right_piece) {
  const SynthFrame f = d.render(k);
  const CameraModel camera(c.camera, f.pose);
  const std::uint8_t asphalt = static_cast<std::uint8_t>(c.synth.asphalt_grey);
  for (int y = 0; y < d.view.height; ++y)
    for (int x = 0; x < d.view.width; ++x) {
      const std::optional<Vec3> p = camera.ground_point_from_pixel(Vec2(x + 1.0, y + 1.0));
      if (!p) continue;
      const bool left_line = p->y() > 0.0 && p->y() < 0.75 * f.lane_width_mm;
      const bool piece =
          right_piece && p->y() < 0.0 && p->y() > -0.75 * f.lane_width_mm && p->x() > 8000.0 && p->x() < 12000.0;
      if (!left_line && !piece) d.px[static_cast<std::size_t>(y * d.view.width + x)] = asphalt;
    }
  return f;
}

Config straight_solid_lines() {
  Config c = small_camera();
  c.synth.weave_mm = 0.0;
  c.synth.dashed = DashedLines::none;
  return c;
}

TEST(LaneEstimator, WithoutALaneTheOwnSidesLinesAreReportedOnTheirOwnSupport) {
  const Config c = straight_solid_lines();
  Drive d(c);
  LaneEstimator est(c.estimator_options());
  const SynthFrame f = render_left_line(d, c, 0, true);
  const LaneEstimate& e = est.estimate(d.view, 0, f.t_ns, f.gyro);
  EXPECT_FALSE(e.ok);
  EXPECT_EQ(e.reason, EstimateFailure::no_lane) << to_string(e.reason);
  ASSERT_EQ(e.num_lines, 1);
  EXPECT_NEAR(e.lines[0].y0_mm, f.lane_width_mm / 2.0, f.lane_width_mm / 4.0) << "the left line";
  // Without a gyro, from a mount configured 6 or 12 degrees off in pitch (a picture's own
  // tilt, which nobody wrote down, and a user's error): no vanishing point (one side's
  // line), the mount's own pose sees nothing, a pose the search pitches by its steps sees
  // the left line, and that is what the still reports.
  for (const double pitch_off : {6.0, 12.0, -12.0}) {
    Config off = c;
    off.attitude.theta_deg += pitch_off;
    off.prior.phi_deg = Prior{0.0, 1.0};
    LaneEstimator searching(off.estimator_options());
    const LaneEstimate& s = searching.estimate(d.view, 0, f.t_ns, std::nullopt);
    EXPECT_EQ(s.reason, EstimateFailure::no_lane) << pitch_off << ": " << to_string(s.reason);
    ASSERT_EQ(s.num_lines, 1) << pitch_off;
    EXPECT_NEAR(s.lines[0].y0_mm, f.lane_width_mm / 2.0, f.lane_width_mm / 4.0) << pitch_off << ": the left line";
  }
}

// A track of lines that makes no lane (one line: a first frame's wrong lines, which each
// frame's priors keep finding, are such a track) is searched afresh after
// kMaxTrackedFramesWithoutLane frames, and tracked again after that search; a drive whose
// lane is ok tracks throughout (AMountFiveDegreesOffIsFoundFromThePicture).
TEST(LaneEstimator, ATrackWithoutALaneIsSearchedAfreshAfterASecond) {
  const Config c = straight_solid_lines();
  Drive d(c);
  LaneEstimator est(c.estimator_options());
  const int n = LaneEstimator::kMaxTrackedFramesWithoutLane;
  for (int k = 0; k <= 2 * n + 2; ++k) {
    const SynthFrame f = render_left_line(d, c, static_cast<std::uint64_t>(k), false);
    const LaneEstimate& e = est.estimate(d.view, static_cast<std::uint64_t>(k), f.t_ns, f.gyro);
    ASSERT_FALSE(e.ok) << k;
    ASSERT_EQ(e.num_lines, 1) << k;
    // Searches at 0, n + 1, 2n + 2: each search's frame is followed by n tracked ones.
    EXPECT_EQ(e.state, k % (n + 1) == 0 ? EstimatorState::searching : EstimatorState::tracking) << k;
  }
}

// The height is acquired once, after a second, and the lines go on rescaled. Where the
// first frame at the new height solves lines but makes no lane (here it shows the left
// line alone; held still 61 found its right line alone there), the next frame searches
// at once, at the new height, instead of tracking a second of frames without a lane. A
// frame without a solve (an empty one) coasts, as any does.
TEST(LaneEstimator, ALaneLostOnTheFrameAfterTheHeightChangedIsSearchedAtOnce) {
  for (const bool solved : {true, false}) {
    const Config truth = straight_solid_lines();
    Drive d(truth);
    LaneEstimator est(height_off(truth, 1.25).estimator_options());
    // The height is acquired at the end of frame n - 1: frame n is the first at it.
    const auto n = static_cast<std::uint64_t>(MountRefinement::kMountAcquisitionFrames);
    double searched_height = 0.0;
    for (std::uint64_t j = 0; j < n; ++j) {
      const SynthFrame f = d.render(j);
      const LaneEstimate& e = est.estimate(d.view, j, f.t_ns, f.gyro);
      ASSERT_TRUE(e.ok) << j;
      searched_height = e.H_mm;
    }
    std::uint64_t k = n;
    SynthFrame f = render_left_line(d, truth, k, false);
    if (!solved) std::fill(d.px.begin(), d.px.end(), static_cast<std::uint8_t>(truth.synth.asphalt_grey));
    const LaneEstimate& lost = est.estimate(d.view, k, f.t_ns, f.gyro);
    ASSERT_FALSE(lost.ok);
    EXPECT_EQ(lost.state, EstimatorState::tracking);
    // The height changed: the search's was a step from the configured one (1346 mm
    // against the truth's 1400 when this was written).
    EXPECT_GT(std::abs(lost.H_mm - searched_height), 0.02 * truth.H_mm) << searched_height << " " << lost.H_mm;
    ++k;
    f = d.render(k);
    const LaneEstimate& e = est.estimate(d.view, k, f.t_ns, f.gyro);
    ASSERT_TRUE(e.ok) << to_string(e.reason);
    EXPECT_EQ(e.state, solved ? EstimatorState::searching : EstimatorState::tracking) << "solved " << solved;
    EXPECT_NEAR(e.H_mm, truth.H_mm, 0.05 * truth.H_mm);
  }
}

// A bump pitches the camera 2 degrees down for one frame. Without a gyro, each frame's
// look starts from the previous frame's pose: the frame after the bump is looked at from
// the bumped pitch, its lines projected splay out of the previous frame's, and the track
// finds no lane. That frame looks once more from the same pose as a search's pose does,
// with the search's wider pitch tolerance and no previous lines, and the lane is there
// (state searching); the frames after it track again. Every frame is ok.
TEST(LaneEstimator, AFrameTheTrackMissesIsLookedAtAfreshFromTheSamePose) {
  Config c = small_camera();
  c.prior.phi_deg = Prior{0.0, 1.0};  // no gyro: roll from the prior
  Drive d(c);
  LaneEstimator est(c.estimator_options());
  constexpr std::uint64_t kBump = 10;
  for (std::uint64_t k = 0; k < 14; ++k) {
    SynthFrame f = d.drive.frame(k);
    if (k == kBump) f.pose.attitude.theta += deg_to_rad(2.0);
    d.renderer.render(f, d.view);
    const LaneEstimate& e = est.estimate(d.view, k, f.t_ns, std::nullopt);
    ASSERT_TRUE(e.ok) << "frame " << k << ": " << to_string(e.reason);
    EXPECT_EQ(e.state, k == 0 || k == kBump + 1 ? EstimatorState::searching : EstimatorState::tracking) << k;
    EXPECT_NEAR(e.theta_deg, rad_to_deg(f.pose.attitude.theta), 3 * e.sigma_theta_deg) << "frame " << k;
  }
}

// From the leftmost of four lanes: the own lane's lines and the one beyond on the right
// are reported, not those two and three lanes off (keep_adjacent_lanes).
TEST(LaneEstimator, TheOwnLanesLinesAndTheNextOnEachSideAreReported) {
  Config c = small_camera();
  c.synth.lanes = 4;
  c.synth.ego_lane = 0;
  c.synth.weave_mm = 0.0;
  c.synth.dashed = DashedLines::none;
  c.detection.max_lines = 4;
  Drive d(c);
  LaneEstimator est(c.estimator_options());
  for (std::uint64_t k = 0; k < 10; ++k) {
    const SynthFrame f = d.render(k);
    const LaneEstimate& e = est.estimate(d.view, k, f.t_ns, f.gyro);
    ASSERT_TRUE(e.ok) << "frame " << k << ": " << to_string(e.reason);
    ASSERT_EQ(e.num_lines, 3) << "frame " << k;
    for (int j = 0; j < 3; ++j) EXPECT_NEAR(e.lines[j].y0_mm, f.y0_mm[j], 100.0) << "frame " << k << " line " << j;
  }
}

TEST(LaneEstimator, EstimatingAllocatesNothing) {
  Config c = small_camera();
  Drive d(c);
  LaneEstimatorOptions options = c.estimator_options();
  options.online_mount = c.online_mount_options();  // the mount's online refinement runs in every frame too
  LaneEstimator est(options);
  std::vector<SynthFrame> frames;
  std::vector<std::vector<std::uint8_t>> images;
  for (std::uint64_t k = 0; k < 4; ++k) {
    frames.push_back(d.render(k));
    images.push_back(d.px);
  }
  auto view = [&](std::size_t i) { return ImageView{images[i].data(), 400, 300, 400, PixelFormat::mono8, 8}; };
  est.estimate(view(0), 0, 0, frames[0].gyro);  // warm: nothing is sized lazily, but be fair
  // The lane departure warning runs in the same call, with every vehicle input given.
  VehicleInputs vehicle;
  vehicle.speed_mps = 20.0;
  vehicle.yaw_rate_radps = 0.001;
  vehicle.indicator = ldw::TurnIndicator::left;
  test::AllocationScope scope;
  for (std::size_t i = 0; i < frames.size(); ++i)
    EXPECT_TRUE(est.estimate(view(i), i, frames[i].t_ns, frames[i].gyro, vehicle).ok);
  const bool ldw_tracked = est.estimate(view(3), 4, frames[3].t_ns + 1'000'000, frames[3].gyro, vehicle).ldw.tracked;
  est.no_frame(5, frames[3].t_ns + 2'000'000, vehicle);  // the filter coasts
  est.reset();                                           // the cold-start path (detect twice) too
  EXPECT_TRUE(est.estimate(view(1), 1, frames[1].t_ns, frames[1].gyro).ok);
  est.no_frame(2, 0);
  EXPECT_EQ(scope.count(), 0u);
  EXPECT_TRUE(ldw_tracked) << "the LDW chain ran on the solves";
}

}  // namespace
}  // namespace ccdlane
