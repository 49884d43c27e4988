// Two refinements of one mount, at two time scales: the start's is a second of frames and
// replaces a mount that is clearly off; the online one is minutes of straight, fast road
// and moves the mount by a bounded correction. While the start's replacement is in use
// the online correction is learned but not applied: the picture has spoken for the run.
#include "core/lane/mount_refinement.hpp"

#include <cmath>

#include "core/geometry/types.hpp"

namespace ccdlane {
namespace {

// Whether yaw or pitch differ by more than `deg`.
bool off_by_more(const Attitude& a, const Attitude& b, double deg) {
  return std::abs(rad_to_deg(a.psi - b.psi)) > deg || std::abs(rad_to_deg(a.theta - b.theta)) > deg;
}

// The road's curvature at the vehicle (|1/R|, per metre) from the solved lines: the
// curvature of y = y0 + m x + c x^2 at x = 0 is 2c; lines of one road share it.
double road_curvature_per_m(const LaneEstimate& e) {
  double sum = 0.0;
  for (int j = 0; j < e.num_lines; ++j) sum += e.lines[static_cast<std::size_t>(j)].c_per_mm;
  return e.num_lines > 0 ? std::abs(2.0 * sum / e.num_lines) * 1e3 : 0.0;
}

calibration::MountSample mount_sample(const LaneEstimate& e, const VehicleInputs& vehicle) {
  calibration::MountSample s;
  s.t_ns = e.t_ns;
  // ok: solved, with a line on each side of the vehicle; a roll that could not be
  // observed leaves yaw and pitch in doubt too.
  s.solved = e.ok && !e.roll_unobservable;
  s.speed_kmh = e.ldw.speed_mps * 3.6;  // the speed LDW used: the vehicle's, else [vehicle] speed_kmh
  s.curvature_per_m = road_curvature_per_m(e);
  if (vehicle.yaw_rate_radps) s.yaw_rate_deg_s = rad_to_deg(*vehicle.yaw_rate_radps);
  s.psi_deg = e.psi_deg;
  s.theta_deg = e.theta_deg;
  return s;
}

}  // namespace

MountRefinement::MountRefinement(const LaneEstimatorOptions& options)
    : configured_(options.nominal_pose.attitude),
      corrected_(configured_),
      mount_(configured_),
      lane_width_prior_(options.priors.lane_width_mm),
      height_known_(height_known(options.priors)),
      configured_height_mm_(options.nominal_pose.H_mm),
      height_mm_(configured_height_mm_) {
  if (!options.online_mount) return;
  online_.emplace(*options.online_mount);
  if (options.learned_mount) online_->restore(*options.learned_mount);
  result_.status = online_->status();
  result_.learned = online_->learned();
  apply_correction();
}

bool MountRefinement::height_known(const SolverPriors& priors) {
  if (!priors.H_mm) return false;
  if (!priors.lane_width_mm) return true;
  return priors.H_mm->sigma / priors.H_mm->mean <= priors.lane_width_mm->sigma / priors.lane_width_mm->mean;
}

void MountRefinement::reset() {
  mount_ = corrected_;
  height_mm_ = configured_height_mm_;
  acquisition_ = Acquisition{};
}

Attitude MountRefinement::mount_for(const Attitude& solved) const {
  // At the start of a run a mount that is clearly off is replaced by the picture's: one
  // frame's solve when it is off by more than twice kMountTrustDeg (one frame's yaw is
  // the mount's plus the vehicle's heading), then the mean of the first second's when
  // that is off by more than kMountTrustDeg (acquire).
  if (!replaced_by(solved)) return mount_;
  Attitude a = corrected_;
  a.psi = solved.psi;
  a.theta = solved.theta;
  return a;
}

bool MountRefinement::replaced_by(const Attitude& solved) const {
  return !acquisition_.done && !acquisition_.adopted && off_by_more(solved, corrected_, 2 * kMountTrustDeg) &&
         !off_by_more(solved, corrected_, kMountReachDeg);
}

void MountRefinement::adopt(const Attitude& solved) {
  if (!replaced_by(solved)) return;
  mount_ = mount_for(solved);
  acquisition_.adopted = true;
}

bool MountRefinement::acquire(const Attitude& solved, double lane_width_mm) {
  // Along a lane the vehicle's heading and pitch average out: the mean of the first ok
  // frames' camera yaw and pitch is the mount (online refinement follows it later, slowly).
  Acquisition& q = acquisition_;
  if (q.done) return false;
  ++q.frames;
  q.psi += solved.psi;
  q.theta += solved.theta;
  q.lane_width_mm += lane_width_mm;
  Attitude mean = corrected_;
  mean.psi = q.psi / q.frames;
  mean.theta = q.theta / q.frames;
  bool rescaled = false;
  if (q.frames >= kMountAcquisitionFrames) {
    q.done = true;
    q.adopted = q.adopted || off_by_more(mean, corrected_, kMountTrustDeg);
    // On a flat road every distance the picture gives scales with the height: a mean
    // width that is clearly not a lane's says the height is off, by their ratio.
    const double width = q.lane_width_mm / q.frames;
    const std::optional<Prior>& prior = lane_width_prior_;
    if (prior && !height_known_ && width > 0.0 && std::abs(width - prior->mean) > kHeightTrustSigmas * prior->sigma) {
      height_mm_ *= prior->mean / width;
      rescaled = true;
    }
  }
  if (q.adopted) mount_ = mean;
  return rescaled;
}

const MountRefinementResult& MountRefinement::refine(const LaneEstimate& e, const VehicleInputs& vehicle) {
  if (!online_) return result_;
  if (e.reason == EstimateFailure::no_frame) {
    result_.used = false;
    return result_;
  }
  result_.used = online_->add(mount_sample(e, vehicle));
  result_.status = online_->status();
  result_.learned = online_->learned();
  apply_correction();
  return result_;
}

bool MountRefinement::calibrated() const {
  return !online_ || online_->state() != calibration::OnlineMountState::out_of_range;
}

void MountRefinement::apply_correction() {
  corrected_.psi = configured_.psi + deg_to_rad(online_->applied().psi_deg);
  corrected_.theta = configured_.theta + deg_to_rad(online_->applied().theta_deg);
  if (!acquisition_.adopted) mount_ = corrected_;
}

}  // namespace ccdlane
