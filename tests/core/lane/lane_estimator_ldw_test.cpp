// The lane departure warning through the whole pipeline: vehicle drives rendered to
// frames (the road renderer), each frame detected, solved, filtered and judged by the
// LaneEstimator, the warning checked against the drive's truth (each front wheel's exact
// distance to its line): one warning, on the drifting side, between the earliest and the
// latest warning line (ISO 17361); none while weaving inside the lane.
#include <cmath>
#include <cstdio>
#include <vector>

#include <gtest/gtest.h>

#include "core/lane/lane_estimator.hpp"
#include "core/ldw/scenarios.hpp"
#include "core/synth/road_renderer.hpp"
#include "core/synth/vehicle_drive.hpp"
#include "tests/core/synth/rendered_road.hpp"

namespace ccdlane {
namespace {

struct Warning {
  double t_s = 0.0;
  ldw::Side side = ldw::Side::none;
  double wheel_dlc_m = 0.0;  // the truth at the warning's frame, that side's wheel
};

struct DriveRun {
  std::vector<Warning> warnings;
  int frames = 0, ok_frames = 0, available_frames = 0;
};

// Renders `spec`'s drive for the small reference camera (the road's widths as the drive
// has them, frames with the gyro's roll and pitch) and runs every frame through one
// LaneEstimator with the drive's speed, the gyro's yaw rate and the indicator.
DriveRun run_rendered(const ldw::ScenarioSpec& spec) {
  Config c = test::small_reference_camera();
  c.detection.max_picks = 160;
  const VehicleScenario& d = spec.drive;
  c.synth.lanes = d.lanes;
  c.synth.ego_lane = d.ego_lane;
  c.synth.lane_width_mm = d.lane_width_m * 1e3;
  c.synth.line_width_mm = d.line_width_m * 1e3;
  c.synth.rate_hz = d.rate_hz;
  c.synth.seed = d.seed;
  c.vehicle = spec.vehicle;
  c.gyro.device = "emulated";  // the frames carry the gyro's roll: the filter does not track it
  const VehicleDrive drive(d, spec.vehicle);
  RoadRenderer renderer(c.camera, c.synth);
  std::vector<std::uint8_t> px(static_cast<std::size_t>(c.camera.Nu * c.camera.Nv));
  const MutableImageView view{px.data(), c.camera.Nu, c.camera.Nv, c.camera.Nu, PixelFormat::mono8, 8};
  LaneEstimator estimator(c.estimator_options());

  DriveRun run;
  for (std::uint64_t k = 0; k < drive.num_frames(); ++k) {
    const VehicleFrame truth = drive.frame(k);
    const SynthFrame f = drive.synth_frame(k, c.nominal_pose(), c.synth.gyro_noise_deg);
    renderer.render(f, view);
    VehicleInputs vehicle;
    vehicle.speed_mps = truth.speed_mps;
    vehicle.yaw_rate_radps = truth.measured_yaw_rate_radps;
    vehicle.indicator = truth.indicator;
    const LaneEstimate& e = estimator.estimate(view, k, f.t_ns, f.gyro, vehicle);
    ++run.frames;
    run.ok_frames += e.ok;
    run.available_frames += e.ldw.available;
    if (e.ldw.fired != ldw::Side::none) {
      const bool left = e.ldw.fired == ldw::Side::left;
      run.warnings.push_back({truth.t_s, e.ldw.fired, left ? truth.wheel_dlc.left_m : truth.wheel_dlc.right_m});
      std::printf("  warning %s at %.2f s: wheel %.3f m inside (filter's DLC %.3f m, TLC %.2f s)\n",
                  ldw::to_string(e.ldw.fired), truth.t_s, run.warnings.back().wheel_dlc_m,
                  (left ? e.ldw.dlc_left_mm : e.ldw.dlc_right_mm) * 1e-3,
                  (left ? e.ldw.tlc_left_s : e.ldw.tlc_right_s).value_or(NAN));
    }
  }
  return run;
}

TEST(LaneEstimatorLdw, RenderedDriftToTheRightIsWarnedOnceBetweenTheWarningLines) {
  // 0.5 m/s toward the right line on a straight road at 72 km/h, after a settled
  // approach shortened to 3 s (the filter confirms its track within a fraction of it).
  ldw::ScenarioSpec spec = ldw::departure_scenario(0.5, ldw::Side::right, 0.0);
  spec.drive.duration_s -= spec.drive.drift_at_s - 3.0;
  spec.drive.drift_at_s = 3.0;
  const DriveRun run = run_rendered(spec);
  const ldw::LdwWarningConfig lines;  // the standard's warning lines, as the defaults have them
  EXPECT_GT(run.ok_frames, run.frames * 9 / 10) << "the pipeline saw the lane";
  EXPECT_GT(run.available_frames, run.frames / 2);
  ASSERT_EQ(run.warnings.size(), 1u);
  EXPECT_EQ(run.warnings[0].side, ldw::Side::right);
  EXPECT_LE(run.warnings[0].wheel_dlc_m * 1e3, lines.earliest_warning_mm) << "warned while still well inside";
  EXPECT_GE(run.warnings[0].wheel_dlc_m * 1e3, lines.latest_warning_mm) << "warned too late";
  EXPECT_GT(run.warnings[0].t_s, spec.drive.drift_at_s) << "not before the drift began";
}

TEST(LaneEstimatorLdw, RenderedWeavingInsideTheLaneGivesNoWarning) {
  // Normal driving's weave (+-0.14 m, the wheels more than 0.75 m inside the lines) for
  // 20 s: a lane the pipeline tracks all along, and never a warning.
  const ldw::ScenarioSpec spec = ldw::normal_driving_scenario(20.0 / 60.0);
  const DriveRun run = run_rendered(spec);
  EXPECT_GT(run.ok_frames, run.frames * 9 / 10);
  EXPECT_GT(run.available_frames, run.frames * 8 / 10) << "LDW was available: the silence means something";
  EXPECT_TRUE(run.warnings.empty()) << run.warnings.size() << " false alarms";
}

}  // namespace
}  // namespace ccdlane
