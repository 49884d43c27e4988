// The lane-state Kalman filter. The measurement is linear in the state (the lines at
// +-w/2 - d, the rest direct); only the prediction's sin(psi) is linearised. Absent
// measurement components are dropped by selecting rows into matrices of fixed maximum
// size, so nothing is allocated.
#include "core/ldw/lane_filter.hpp"

#include <cmath>
#include <limits>

#include <Eigen/Cholesky>

#include "core/ldw/chi_square.hpp"

namespace ccdlane::ldw {
namespace {

using Dyn = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMeasurementSize, kMeasurementSize>;
using DynRows = Eigen::Matrix<double, Eigen::Dynamic, kStateSize, 0, kMeasurementSize, kStateSize>;
using DynCols = Eigen::Matrix<double, kStateSize, Eigen::Dynamic, 0, kStateSize, kMeasurementSize>;
using DynVector = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMeasurementSize, 1>;

using MeasurementJacobian = Eigen::Matrix<double, kMeasurementSize, kStateSize>;

// d(measurement)/d(state): the lines at w/2 - d and -w/2 - d, the heading plus its bias,
// the rest one to one.
MeasurementJacobian measurement_jacobian() {
  MeasurementJacobian H = MeasurementJacobian::Zero();
  H(kLeftLine, kOffset) = -1.0;
  H(kLeftLine, kWidth) = 0.5;
  H(kRightLine, kOffset) = -1.0;
  H(kRightLine, kWidth) = -0.5;
  H(kMeasuredHeading, kHeading) = 1.0;
  H(kMeasuredHeading, kHeadingBias) = 1.0;
  H(kMeasuredCurvature, kCurvature) = 1.0;
  H(kMeasuredPitch, kPitch) = 1.0;
  H(kMeasuredRoll, kRoll) = 1.0;
  return H;
}

// The state moved into the neighbour lane on `side` (+1 left, -1 right): the offset
// from the new lane's centre is d -+ w.
StateMatrix neighbour_lane_shift(int side) {
  StateMatrix J = StateMatrix::Identity();
  J(kOffset, kWidth) = -side;
  return J;
}

}  // namespace

const char* to_string(TrackStatus s) {
  switch (s) {
    case TrackStatus::lost: return "lost";
    case TrackStatus::tentative: return "tentative";
    case TrackStatus::tracking: return "tracking";
    case TrackStatus::coasting: return "coasting";
  }
  return "?";
}

const char* to_string(LaneChange c) {
  switch (c) {
    case LaneChange::none: return "none";
    case LaneChange::left: return "left";
    case LaneChange::right: return "right";
  }
  return "?";
}

LaneFilter::LaneFilter(const LaneFilterConfig& config) : config_(config) {
  for (int n = 1; n <= kMeasurementSize; ++n)
    gate_[static_cast<std::size_t>(n)] = chi_square_quantile(n, config_.gate_probability);
  reset_mount();
}

void LaneFilter::reset_mount() {
  reset();
  bias_ = 0.0;
  bias_variance_ = config_.initial_heading_bias_rad * config_.initial_heading_bias_rad;
}

void LaneFilter::reset() {
  if (accepted_ > 0) {  // a track ends: keep what it learnt of the mount
    bias_ = x_(kHeadingBias);
    bias_variance_ = P_(kHeadingBias, kHeadingBias);
  }
  x_.setZero();
  P_.setZero();
  accepted_ = 0;
  state_ = LaneState{};
  publish();
}

void LaneFilter::predict(double dt_s, const VehicleMotion& motion) {
  speed_mps_ = motion.speed_mps;
  yaw_rate_radps_ = motion.yaw_rate_radps;
  state_.updated = state_.rejected = state_.restarted = false;
  state_.lane_change = LaneChange::none;
  if (state_.status == TrackStatus::lost) return;

  const double v = motion.speed_mps, dt = dt_s;
  const double psi = x_(kHeading), cos_psi = std::cos(psi);
  StateMatrix F = StateMatrix::Identity();
  F(kOffset, kHeading) = v * cos_psi * dt;
  x_(kOffset) += v * std::sin(psi) * dt;
  if (motion.yaw_rate_radps) {
    x_(kHeading) += (*motion.yaw_rate_radps - v * x_(kCurvature)) * dt;
    F(kHeading, kCurvature) = -v * dt;
  }

  const double q_heading = motion.yaw_rate_radps ? config_.heading_noise_rad : config_.heading_noise_no_yaw_rate_rad;
  StateVector q;
  q << config_.offset_noise_m, q_heading, config_.curvature_noise_per_m, config_.width_noise_m, config_.pitch_noise_rad,
      config_.track_roll ? config_.roll_noise_rad : 0.0, config_.heading_bias_noise_rad;
  StateMatrix Q = (q.array().square() * dt).matrix().asDiagonal();
  // The heading's random walk, integrated, moves the offset too.
  const double qh2 = q_heading * q_heading, vc = v * cos_psi;
  Q(kOffset, kOffset) += vc * vc * qh2 * dt * dt * dt / 3.0;
  Q(kOffset, kHeading) = Q(kHeading, kOffset) = vc * qh2 * dt * dt / 2.0;
  P_ = F * P_ * F.transpose() + Q;

  state_.since_update_s += dt;
  if (state_.since_update_s > config_.coast_s) {
    reset();
    return;
  }
  publish();
}

void LaneFilter::initialise(const LaneMeasurement& m) {
  // z -> x: d = -(yl + yr) / 2, w = yl - yr, the rest one to one.
  Eigen::Matrix<double, kStateSize, kMeasurementSize> T = Eigen::Matrix<double, kStateSize, kMeasurementSize>::Zero();
  T(kOffset, kLeftLine) = T(kOffset, kRightLine) = -0.5;
  T(kWidth, kLeftLine) = 1.0;
  T(kWidth, kRightLine) = -1.0;
  T(kHeading, kMeasuredHeading) = T(kCurvature, kMeasuredCurvature) = 1.0;
  T(kPitch, kMeasuredPitch) = T(kRoll, kMeasuredRoll) = 1.0;
  MeasurementVector z = m.value;
  MeasurementMatrix R = m.covariance;
  StateVector initial_sigma;
  initial_sigma << 0.0, config_.initial_heading_rad, config_.initial_curvature_per_m, 0.0, config_.initial_pitch_rad,
      config_.initial_roll_rad, 0.0;
  StateVector absent_variance = StateVector::Zero();
  for (int i = kMeasuredHeading; i < kMeasurementSize; ++i) {
    const bool use = m.present[static_cast<std::size_t>(i)] && (i != kMeasuredRoll || config_.track_roll);
    if (use) continue;
    z(i) = 0.0;
    R.row(i).setZero();
    R.col(i).setZero();
    const int s = i - kMeasuredHeading + kHeading;  // the state this component measures
    absent_variance(s) = (s == kRoll && !config_.track_roll) ? 0.0 : initial_sigma(s) * initial_sigma(s);
  }
  x_ = T * z;
  P_ = T * R * T.transpose();
  P_.diagonal() += absent_variance;
  // The measured heading is the heading plus the bias the previous tracks left (or the
  // prior): heading = measured - bias, correlated with it.
  x_(kHeadingBias) = bias_;
  P_(kHeadingBias, kHeadingBias) = bias_variance_;
  if (m.present[kMeasuredHeading]) {
    x_(kHeading) -= bias_;
    P_(kHeading, kHeading) += bias_variance_;
    P_(kHeading, kHeadingBias) = P_(kHeadingBias, kHeading) = -bias_variance_;
  }
  accepted_ = 1;
  state_.since_update_s = 0.0;
  state_.updated = true;
  state_.nis = 0.0;
  state_.nis_dof = 0;
  state_.status = TrackStatus::tentative;
  publish();
}

void LaneFilter::update(const LaneMeasurement& m) {
  state_.updated = state_.rejected = state_.restarted = false;
  state_.lane_change = LaneChange::none;
  if (state_.status == TrackStatus::lost) {
    if (m.present[kLeftLine] && m.present[kRightLine]) initialise(m);
    return;
  }
  // The rows of this measurement that count.
  std::array<int, kMeasurementSize> rows{};
  int n = 0;
  for (int i = 0; i < kMeasurementSize; ++i)
    if (m.present[static_cast<std::size_t>(i)] && (i != kMeasuredRoll || config_.track_roll))
      rows[static_cast<std::size_t>(n++)] = i;
  if (n == 0) return;
  static const MeasurementJacobian H_full = measurement_jacobian();
  DynRows H(n, kStateSize);
  DynVector z(n);
  Dyn R(n, n);
  for (int a = 0; a < n; ++a) {
    const int i = rows[static_cast<std::size_t>(a)];
    H.row(a) = H_full.row(i);
    z(a) = m.value(i);
    for (int b = 0; b < n; ++b) R(a, b) = m.covariance(i, rows[static_cast<std::size_t>(b)]);
  }

  // Own lane, or the neighbour on either side: the hypothesis the measurement fits best.
  double best = std::numeric_limits<double>::infinity();
  int best_side = 0;
  for (const int side : {0, 1, -1}) {
    const StateMatrix J = neighbour_lane_shift(side);
    const DynVector innovation = z - H * (J * x_);
    const Dyn S = H * (J * P_ * J.transpose()) * H.transpose() + R;
    const Eigen::LLT<Dyn> llt(S);
    if (llt.info() != Eigen::Success) continue;
    const double d2 = innovation.dot(llt.solve(innovation));
    if (d2 < best) best = d2, best_side = side;
  }
  if (!(best <= gate_[static_cast<std::size_t>(n)])) {
    if (++state_.rejections > config_.max_rejections && m.present[kLeftLine] && m.present[kRightLine]) {
      reset();
      initialise(m);
      state_.restarted = true;
      return;
    }
    state_.rejected = true;
    publish();
    return;
  }
  state_.rejections = 0;
  if (best_side != 0) {
    const StateMatrix J = neighbour_lane_shift(best_side);
    x_ = J * x_;
    P_ = J * P_ * J.transpose();
    state_.lane_change = best_side > 0 ? LaneChange::left : LaneChange::right;
  }

  const DynVector innovation = z - H * x_;
  const Dyn S = H * P_ * H.transpose() + R;
  const Eigen::LLT<Dyn> llt(S);
  const DynCols PHt = P_ * H.transpose();
  const DynCols K = llt.solve(PHt.transpose()).transpose();
  x_ += K * innovation;
  // Joseph form: stays symmetric and positive semi-definite whatever the rounding.
  const StateMatrix I_KH = StateMatrix::Identity() - K * H;
  P_ = I_KH * P_ * I_KH.transpose() + K * R * K.transpose();
  P_ = 0.5 * (P_ + P_.transpose()).eval();

  ++accepted_;
  state_.since_update_s = 0.0;
  state_.updated = true;
  state_.nis = best;
  state_.nis_dof = n;
  publish();
}

const LaneState& LaneFilter::step(double dt_s, const VehicleMotion& motion, const LaneMeasurement* measurement) {
  predict(dt_s, motion);
  if (measurement) update(*measurement);
  return state_;
}

void LaneFilter::publish() {
  LaneState& s = state_;
  if (accepted_ == 0) {
    s.status = TrackStatus::lost;
  } else if (accepted_ < config_.confirm_updates) {
    s.status = TrackStatus::tentative;
  } else {
    s.status = s.updated ? TrackStatus::tracking : TrackStatus::coasting;
  }
  s.value = x_;
  s.sigma = P_.diagonal().cwiseMax(0.0).cwiseSqrt();
  if (!config_.track_roll) s.sigma(kRoll) = std::numeric_limits<double>::quiet_NaN();
  const double v = speed_mps_, psi = x_(kHeading);
  s.lateral_velocity_mps = v * std::sin(psi);
  s.sigma_lateral_velocity_mps = std::abs(v * std::cos(psi)) * s.sigma(kHeading);
  s.lateral_acceleration_mps2 = yaw_rate_radps_ ? v * (*yaw_rate_radps_ - v * x_(kCurvature)) : 0.0;
}

}  // namespace ccdlane::ldw
