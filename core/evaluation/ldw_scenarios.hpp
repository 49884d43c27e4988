// The lane departure warning's scenarios (ISO 17361 warning generation, repeatability,
// false alarms; suppression; coasting) run on the vehicle drive's truth, and the summary
// table `ccdlane ldw-scenarios` prints. The per-frame solve is stood in for by the truth
// plus noise of the size the solver's covariance reports on synthetic frames (below), so
// the warning logic and the filter are judged here; rendered frames through the whole
// pipeline are the integrator's next step.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/ldw/ldw_monitor.hpp"
#include "core/synth/vehicle_drive.hpp"

namespace ccdlane::ldw {

// The per-frame solve's errors: the solver's reported covariance on rendered 3-lane
// frames (reference camera, curvature free, gyro roll prior 0.5 deg), mapped to the
// measurement: the lines' y0 33 mm each, correlated 0.85 (both move with the roll),
// heading 1.3 mrad (0.075 deg), curvature 1e-4 1/m, pitch 0.8 mrad. Roll comes from the
// gyro and is not measured here.
struct MeasurementNoise {
  double line_m = 0.033;
  double line_correlation = 0.85;
  double heading_rad = 0.0013;
  double curvature_per_m = 1.0e-4;
  double pitch_rad = 0.0008;
  double scale = 1.0;  // all of the above times this
};

// The measurement of truth frame `f`: the truth plus a draw from `noise`'s covariance
// (seeded by `seed` and the frame), with that covariance.
LaneMeasurement noisy_measurement(const VehicleFrame& f, const MeasurementNoise& noise, std::uint64_t seed);

struct DropWindow {
  double from_s = 0.0, to_s = 0.0;  // frames in [from, to) have no measurement
};

struct ScenarioSpec {
  std::string name;
  VehicleScenario drive;
  VehicleConfig vehicle;
  MeasurementNoise noise;
  std::vector<DropWindow> drops;
  bool yaw_rate = true;  // feed the gyro's yaw rate to the filter
  // What should happen: the side of the one departure to be warned, or none for a drive
  // that must give no warning at all.
  Side expect = Side::none;
};

struct WarningEvent {
  double t_s = 0.0;
  Side side = Side::none;
  double wheel_dlc_m = 0.0;           // the truth: that side's front wheel at the warning, + inside
  double lateral_velocity_mps = 0.0;  // the truth, toward that side
};

struct ScenarioRun {
  std::vector<WarningEvent> warnings;
  int frames = 0;
  int available_frames = 0;
  std::optional<Availability> last_unavailable;  // the reason of the last unavailable frame
  // NEES of (offset, heading, curvature, width, pitch) per frame (NaN while not tracked).
  std::vector<double> nees;
  int lane_changes = 0;  // re-associations of the filter
  double duration_s = 0.0;
  // The warning came as expected: one, on the expected side, the wheel between the
  // latest and earliest warning lines (or none at all when none is expected).
  bool passed = false;
};

// Every frame's truth of the spec's drive (drive.seed: its weave, bumps and sway).
std::vector<VehicleFrame> drive_truth(const ScenarioSpec& spec);
// One run over that truth, the solve's noise and the gyro's yaw-rate noise drawn from
// `noise_seed`: the same drive with another noise, as the standard's repeatability asks.
ScenarioRun run_scenario(const ScenarioSpec& spec, const std::vector<VehicleFrame>& truth, std::uint64_t noise_seed,
                         const LdwConfig& config);
// Drive and noise both from `seed` (another drive per seed).
ScenarioRun run_scenario(const ScenarioSpec& spec, std::uint64_t seed, const LdwConfig& config);

// Degrees of freedom of the NEES above.
constexpr int kNeesDof = 5;

// The scenario families. `departure`: a settled approach 0.4 m off the lane centre away
// from `side`, then a drift at `lateral_mps` toward `side` (reached within 1 s, before
// the warning zone) on a road of that curvature (0 straight) until the wheel is 0.5 m out.
ScenarioSpec departure_scenario(double lateral_mps, Side side, double curvature_per_m);
// Normal driving for `minutes`: weaving within +-0.14 m (the wheels > 0.75 m inside a
// 3.75 m lane with a 1.8 m vehicle), curves of R 500..800 m both ways, and signalled lane
// changes. No warning expected.
ScenarioSpec normal_driving_scenario(double minutes);
// A lane change to `side`, with or without the indicator.
ScenarioSpec lane_change_scenario(Side side, bool signalled);

struct SummaryRow {
  std::string road;  // "straight", "curve left", "curve right"
  double lateral_mps = 0.0;
  Side side = Side::none;
  int runs = 0, passed = 0;
  std::vector<double> wheel_dlc_m;  // at each run's first warning
};

struct ScenarioSummary {
  std::vector<SummaryRow> rows;
  int normal_runs = 0;
  double normal_hours = 0.0;
  int false_alarms = 0;
  int suppression_runs = 0, suppression_passed = 0;  // signalled, unsignalled, too slow
  double earliest_m = 0.75, latest_m = -0.3;
};

// Runs the full set: 5 lateral velocities x 2 sides x 3 roads x `seeds` noise seeds,
// `seeds` normal drives of `normal_minutes` (each its own drive), and the suppression
// cases x `seeds` noise seeds.
ScenarioSummary run_scenarios(int seeds, double normal_minutes, const LdwConfig& config);

// The table (plain text, fixed width).
std::string format_summary(const ScenarioSummary& summary);

}  // namespace ccdlane::ldw
