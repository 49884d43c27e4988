// The LDW scenarios of ISO 17361 / UN R130 on the vehicle drive's truth, short enough
// for CI: warning generation (5 lateral velocities x 2 sides x straight and both curves,
// 20 noise seeds on each drive: every departure warned once, the wheel between the earliest and
// latest warning lines), false alarms in normal driving, suppression, filter consistency
// on the drives, coasting through dropped frames, and the summary table.
#include "core/evaluation/ldw_scenarios.hpp"

#include <algorithm>
#include <cmath>
#include <iostream>

#include <gtest/gtest.h>

#include "core/ldw/chi_square.hpp"

namespace ccdlane::ldw {
namespace {

// 20 noise seeds per case and three 5-minute normal drives, as the issue asks. Debug
// builds (CI's sanitizer stage, there for memory errors and undefined behaviour: at -O1
// and instrumented some 40 times slower per seed, at -O0 several hundred) take 3 seeds
// and one drive: every code path, not the statistics.
#ifdef NDEBUG
constexpr int kSeeds = 20;
constexpr int kNormalDrives = 3;
constexpr int kSummarySeeds = 2;
#else
constexpr int kSeeds = 3;
constexpr int kNormalDrives = 1;
constexpr int kSummarySeeds = 1;
#endif
constexpr double kVelocities[] = {0.1, 0.3, 0.5, 0.8, 1.0};

void expect_every_departure_warned(double curvature, bool yaw_rate = true) {
  const LdwConfig config;
  for (const double v : kVelocities)
    for (const Side side : {Side::left, Side::right}) {
      ScenarioSpec spec = departure_scenario(v, side, curvature);
      spec.yaw_rate = yaw_rate;
      const std::vector<VehicleFrame> truth = drive_truth(spec);
      std::vector<double> at;
      for (int seed = 1; seed <= kSeeds; ++seed) {
        const ScenarioRun run = run_scenario(spec, truth, static_cast<std::uint64_t>(seed), config);
        ASSERT_EQ(run.warnings.size(), 1u) << spec.name << " seed " << seed;
        const WarningEvent& w = run.warnings[0];
        EXPECT_EQ(w.side, side) << spec.name << " seed " << seed;
        EXPECT_LE(w.wheel_dlc_m, 0.75) << spec.name << " seed " << seed;   // not before the earliest line
        EXPECT_GE(w.wheel_dlc_m, -0.30) << spec.name << " seed " << seed;  // nor after the latest
        EXPECT_NEAR(w.lateral_velocity_mps, v, 0.01) << spec.name;         // the drift was at its speed
        EXPECT_TRUE(run.passed);
        at.push_back(w.wheel_dlc_m);
      }
      std::sort(at.begin(), at.end());
      std::cout << spec.name << (yaw_rate ? "" : ", no yaw rate") << ": wheel " << at.front() << " / "
                << at[at.size() / 2] << " / " << at.back() << " m inside at the warning (min/median/max)\n";
    }
}

TEST(LdwScenarios, WarningGenerationOnAStraightRoad) { expect_every_departure_warned(0.0); }
TEST(LdwScenarios, WarningGenerationInALeftCurveOfRadius500m) { expect_every_departure_warned(1.0 / 500); }
TEST(LdwScenarios, WarningGenerationInARightCurveOfRadius500m) { expect_every_departure_warned(-1.0 / 500); }
TEST(LdwScenarios, WarningGenerationWithoutTheGyrosYawRate) { expect_every_departure_warned(1.0 / 500, false); }

TEST(LdwScenarios, NormalDrivingGivesNoWarning) {
  const LdwConfig config;
  const ScenarioSpec spec = normal_driving_scenario(5.0);
  for (int seed = 1; seed <= kNormalDrives; ++seed) {  // each its own drive (weave phases)
    const ScenarioRun run = run_scenario(spec, static_cast<std::uint64_t>(seed), config);
    EXPECT_TRUE(run.warnings.empty()) << "seed " << seed << ": " << run.warnings.size() << " warnings, first at "
                                      << (run.warnings.empty() ? 0.0 : run.warnings[0].t_s) << " s";
    // It was a fair test: LDW was available nearly all along, and the lane changes were
    // followed (each one re-associates the filter once).
    EXPECT_GT(run.available_frames, 0.95 * run.frames) << "seed " << seed;
    EXPECT_EQ(run.lane_changes, static_cast<int>(spec.drive.lane_changes.size())) << "seed " << seed;
  }
}

TEST(LdwScenarios, NormalDrivingKeepsTheWheelsOutsideTheWarningZone) {
  // The drive itself: the truth never comes nearer than the earliest warning line
  // outside the signalled lane changes (else "no warning" would prove nothing).
  const ScenarioSpec spec = normal_driving_scenario(5.0);
  const VehicleDrive drive(spec.drive, spec.vehicle);
  double nearest = 1e9;
  for (std::uint64_t k = 0; k < drive.num_frames(); k += 3) {
    const VehicleFrame f = drive.frame(k);
    bool changing = false;
    for (const LaneChangeManoeuvre& lc : spec.drive.lane_changes)
      changing |= f.t_s > lc.start_s - 0.5 && f.t_s < lc.start_s + lc.duration_s + 2.0;
    if (!changing) nearest = std::min({nearest, f.wheel_dlc.left_m, f.wheel_dlc.right_m});
  }
  EXPECT_GT(nearest, 0.75);
}

TEST(LdwScenarios, UnsignalledLaneChangeIsWarnedSignalledIsNot) {
  const LdwConfig config;
  for (const Side side : {Side::left, Side::right}) {
    const ScenarioSpec unsignalled_spec = lane_change_scenario(side, false),
                       signalled_spec = lane_change_scenario(side, true);
    const std::vector<VehicleFrame> unsignalled_truth = drive_truth(unsignalled_spec);
    const std::vector<VehicleFrame> signalled_truth = drive_truth(signalled_spec);
    for (int seed = 1; seed <= kSeeds; ++seed) {
      const ScenarioRun unsignalled =
          run_scenario(unsignalled_spec, unsignalled_truth, static_cast<std::uint64_t>(seed), config);
      ASSERT_EQ(unsignalled.warnings.size(), 1u) << to_string(side) << " seed " << seed;
      EXPECT_EQ(unsignalled.warnings[0].side, side);
      EXPECT_TRUE(unsignalled.passed);
      EXPECT_EQ(unsignalled.lane_changes, 1);
      const ScenarioRun signalled =
          run_scenario(signalled_spec, signalled_truth, static_cast<std::uint64_t>(seed), config);
      EXPECT_TRUE(signalled.warnings.empty()) << to_string(side) << " seed " << seed;
      EXPECT_EQ(signalled.lane_changes, 1);
    }
  }
}

TEST(LdwScenarios, BelowTheSpeedThresholdADriftIsNotWarned) {
  const LdwConfig config;
  for (const Side side : {Side::left, Side::right}) {
    ScenarioSpec spec = departure_scenario(0.5, side, 0.0);
    spec.drive.speed_kmh = 50.0;
    const std::vector<VehicleFrame> truth = drive_truth(spec);
    for (int seed = 1; seed <= kSeeds; ++seed) {
      const ScenarioRun run = run_scenario(spec, truth, static_cast<std::uint64_t>(seed), config);
      EXPECT_TRUE(run.warnings.empty());
      EXPECT_EQ(run.available_frames, 0);
      EXPECT_EQ(run.last_unavailable, Availability::too_slow);
    }
  }
}

// NEES of (offset, heading, curvature, width, pitch) on the drives, averaged over the 20
// seeds at each frame once tracked: 20 * mean is chi-square with 100 degrees of freedom
// if the filter is consistent. The drives' road and width are fixed while the model lets
// them wander (random walks), so the filter is conservative there: the test is that it
// is never overconfident (mean within the upper 99.5 % bound at 99 % of the frames) and
// not uselessly cautious (overall mean above half the degrees of freedom).
TEST(LdwScenarios, FilterIsConsistentOnTheDrives) {
  const LdwConfig config;
  const double upper = chi_square_quantile(kSeeds * kNeesDof, 0.995) / kSeeds;
  for (const double curvature : {0.0, 1.0 / 500}) {
    for (const double v : {0.1, 1.0}) {
      const ScenarioSpec spec = departure_scenario(v, Side::left, curvature);
      const std::vector<VehicleFrame> truth = drive_truth(spec);
      std::vector<double> mean;
      std::vector<int> count;
      for (int seed = 1; seed <= kSeeds; ++seed) {
        const ScenarioRun run = run_scenario(spec, truth, static_cast<std::uint64_t>(seed), config);
        mean.resize(run.nees.size(), 0.0);
        count.resize(run.nees.size(), 0);
        for (std::size_t k = 0; k < run.nees.size(); ++k)
          if (!std::isnan(run.nees[k])) mean[k] += run.nees[k], ++count[k];
      }
      int frames = 0, within = 0;
      double overall = 0.0;
      for (std::size_t k = 0; k < mean.size(); ++k) {
        if (count[k] != kSeeds) continue;
        const double m = mean[k] / kSeeds;
        ++frames;
        within += m <= upper;
        overall += m;
      }
      overall /= frames;
      std::cout << spec.name << ": mean NEES " << overall << " (" << kNeesDof << " dof), " << within << " of " << frames
                << " frames under " << upper << "\n";
      EXPECT_GT(frames, 100);
      EXPECT_GE(within, 0.99 * frames) << spec.name;
      EXPECT_GT(overall, 0.5 * kNeesDof) << spec.name;
    }
  }
}

TEST(LdwScenarios, DroppedFramesMidDriftStillGiveATimelyWarning) {
  const LdwConfig config;
  for (const double v : {0.3, 0.5, 1.0})
    for (const Side side : {Side::left, Side::right}) {
      ScenarioSpec spec = departure_scenario(v, side, 1.0 / 500);
      // Ten frames (a third of a second) lost just before the warning is due: from where
      // the wheel is 0.15 m outside the threshold.
      const std::vector<VehicleFrame> truth = drive_truth(spec);
      const double due = LdwWarning(config.warning).threshold_mm(v) * 1e-3 + 0.15;
      double from = 0.0;
      for (const VehicleFrame& f : truth) {
        if ((side == Side::left ? f.wheel_dlc.left_m : f.wheel_dlc.right_m) <= due) {
          from = f.t_s;
          break;
        }
      }
      ASSERT_GT(from, 0.0);
      spec.drops.push_back({from, from + 10.0 / spec.drive.rate_hz});
      for (int seed = 1; seed <= kSeeds; ++seed) {
        const ScenarioRun run = run_scenario(spec, truth, static_cast<std::uint64_t>(seed), config);
        ASSERT_EQ(run.warnings.size(), 1u) << spec.name << " seed " << seed;
        EXPECT_TRUE(run.passed) << spec.name << " seed " << seed << ": wheel " << run.warnings[0].wheel_dlc_m;
      }
    }
}

TEST(LdwScenarios, SummaryTableCoversEveryCase) {
  const ScenarioSummary s = run_scenarios(kSummarySeeds, 1.0, LdwConfig{});
  ASSERT_EQ(s.rows.size(), 30u);  // 3 roads x 5 velocities x 2 sides
  for (const SummaryRow& r : s.rows) {
    EXPECT_EQ(r.runs, kSummarySeeds);
    EXPECT_EQ(r.passed, kSummarySeeds) << r.road << " " << r.lateral_mps << " " << to_string(r.side);
  }
  EXPECT_EQ(s.false_alarms, 0);
  EXPECT_NEAR(s.normal_hours, kSummarySeeds / 60.0, 1e-3);
  EXPECT_EQ(s.suppression_passed, s.suppression_runs);
  const std::string table = format_summary(s);
  EXPECT_NE(table.find("curve right     1.0 right"), std::string::npos) << table;
  EXPECT_NE(table.find("false alarms per hour"), std::string::npos);
  std::cout << table;
}

}  // namespace
}  // namespace ccdlane::ldw
