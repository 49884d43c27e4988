// Mount calibration from a drive: frames are sorted into straight stretches (no bend, no
// turn, no lane change), the stretches cut into blocks, and the block means averaged; the
// blocks' spread gives the sigmas.
#include "core/calibration/mount_calibration.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

namespace ccdlane::calibration {
namespace {

double wrap_deg(double a) {
  a = std::fmod(a + 180.0, 360.0);
  return (a < 0.0 ? a + 360.0 : a) - 180.0;
}

// A quantity's mean over the kept frames and its standard error: the spread of its block
// means (they, not single frames, are nearly independent), never below what the frames'
// own sigmas allow.
struct Mean {
  double value = 0.0;
  double sigma = 0.0;
};

// `frame_var_sum`: the frames' own variances summed over `frames` frames; their mean
// counts once per block, frames within a block sharing most of their errors (the same
// paint, the same heading).
Mean block_mean(const std::vector<double>& block_means, const std::vector<int>& block_frames, double frame_var_sum,
                int frames) {
  double n = 0.0, sum = 0.0;
  for (std::size_t b = 0; b < block_means.size(); ++b) {
    n += block_frames[b];
    sum += block_frames[b] * block_means[b];
  }
  const double mean = sum / n;
  double spread = 0.0;
  for (std::size_t b = 0; b < block_means.size(); ++b) {
    const double d = block_frames[b] * (block_means[b] - mean);
    spread += d * d;
  }
  const double k = static_cast<double>(block_means.size());
  const double scatter = std::sqrt(spread * k / (k - 1.0)) / n;
  const double formal = std::sqrt(frame_var_sum / frames / k);
  return {mean, std::max(scatter, formal)};
}

}  // namespace

LaneEstimatorOptions mount_estimator_options(LaneEstimatorOptions options, double phi_deg) {
  options.solver.line_model = LineModel::shared_curvature;
  options.solver.free.remove(FreeParam::c);
  options.solver.free.remove(FreeParam::H);
  options.solver.free.remove(FreeParam::f);
  options.solver.free.remove(FreeParam::m);
  options.solver.free.remove(FreeParam::phi);
  options.solver.free.add(FreeParam::psi);
  options.solver.free.add(FreeParam::theta);
  options.solver.free.add(FreeParam::y0);
  options.nominal_pose.attitude.phi = deg_to_rad(phi_deg);
  options.priors.psi_deg.reset();
  options.priors.theta_deg.reset();
  options.priors.phi_deg.reset();
  options.priors.H_mm.reset();
  options.priors.lane_width_mm.reset();
  return options;
}

std::optional<double> equal_lanes_roll_deg(std::span<const double> y0_mm, double H_mm) {
  const std::size_t n = y0_mm.size();
  if (n < 3) return std::nullopt;
  // Seen from above the camera, a line at offset y lies at angle atan(y / H) from the
  // vertical through the vanishing point; a roll d turns every such angle by d. The
  // lines' angles at the true roll are the ones whose tangents are equally spaced:
  // least squares of the spacings' deviation from their mean, by Newton in d.
  const auto spread = [&](double d) {
    double mean = 0.0, sum2 = 0.0;
    double u[kMaxLaneLines + 1];
    for (std::size_t j = 0; j < n && j <= kMaxLaneLines; ++j) u[j] = std::tan(std::atan(y0_mm[j] / H_mm) - d);
    const std::size_t m = std::min<std::size_t>(n, kMaxLaneLines + 1);
    for (std::size_t j = 0; j + 1 < m; ++j) mean += u[j] - u[j + 1];
    mean /= static_cast<double>(m - 1);
    for (std::size_t j = 0; j + 1 < m; ++j) sum2 += (u[j] - u[j + 1] - mean) * (u[j] - u[j + 1] - mean);
    return sum2;
  };
  double d = 0.0;
  constexpr double h = 1e-5;
  for (int it = 0; it < 20; ++it) {
    const double s0 = spread(d), sp = spread(d + h), sm = spread(d - h);
    const double g = (sp - sm) / (2 * h), H = (sp - 2 * s0 + sm) / (h * h);
    if (!(H > 0.0)) return std::nullopt;
    const double step = g / H;
    d -= step;
    if (std::abs(step) < 1e-9) break;
  }
  return rad_to_deg(d);
}

MountFrame mount_frame(const LaneEstimate& e, const SolveResult* solution, const std::optional<Gx1Angles>& gyro,
                       double phi_deg, double nominal_H_mm) {
  MountFrame f;
  f.t_ns = e.t_ns;
  if (gyro) f.gyro_yaw_deg = gyro->yaw_deg;
  f.lane = e.ok && std::isfinite(e.sigma_psi_deg) && std::isfinite(e.sigma_theta_deg);
  f.psi_deg = e.psi_deg;
  f.theta_deg = e.theta_deg;
  f.sigma_psi_deg = e.sigma_psi_deg;
  f.sigma_theta_deg = e.sigma_theta_deg;
  double y0[kMaxLaneLines];
  for (int j = 0; j < e.num_lines; ++j) y0[j] = e.lines[static_cast<std::size_t>(j)].y0_mm;
  if (const auto d = equal_lanes_roll_deg({y0, static_cast<std::size_t>(e.num_lines)}, nominal_H_mm))
    f.phi_deg = phi_deg - *d;
  f.lane_width_mm = e.lane_width_mm;
  f.lateral_offset_mm = e.lateral_offset_mm;
  // The own lane's lines: the nearest on either side of the camera.
  double left = kUndetermined, right = kUndetermined, left_y = 1e300, right_y = -1e300;
  for (int j = 0; j < e.num_lines; ++j) {
    const EstimatedLine& l = e.lines[static_cast<std::size_t>(j)];
    if (l.y0_mm >= 0.0 && l.y0_mm < left_y) left_y = l.y0_mm, left = l.sigma_y0_mm;
    if (l.y0_mm < 0.0 && l.y0_mm > right_y) right_y = l.y0_mm, right = l.sigma_y0_mm;
  }
  f.sigma_lane_width_mm = std::hypot(left, right);
  f.lane = f.lane && std::isfinite(f.sigma_lane_width_mm);
  const bool curvature_known = solution && solution->num_lines > 0 && std::isfinite(solution->sigma.c_per_mm[0]);
  f.c_per_mm = curvature_known ? solution->lines[0].c_per_mm : std::nan("");
  return f;
}

namespace {

constexpr int kMinBlocks = 3;  // fewer give no spread worth the name

double seconds(std::int64_t t_ns) { return 1e-9 * static_cast<double>(t_ns); }

// A bend sharper than min_radius_m (or a curvature the solve could not tell).
bool on_bend(const MountFrame& f, const MountOptions& o) {
  return !(std::abs(f.c_per_mm) <= 1.0 / (2.0 * o.min_radius_m * 1000.0));
}

// Which frames show the lane on straight road with the vehicle neither turning nor moving
// sideways, counted into `r`; and, apart, the times the vehicle crossed a line.
std::vector<bool> straight_frames(std::span<const MountFrame> frames, const MountOptions& o, MountCalibration& r,
                                  std::vector<double>& lane_change_t) {
  std::vector<bool> keep(frames.size(), false);
  int last_lane = -1;
  int window_start = -1;  // the first lane frame within the lateral speed's window, since the last crossing
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const MountFrame& f = frames[i];
    if (!f.lane) continue;
    ++r.frames_with_lane;
    bool ok = true;
    if (on_bend(f, o)) {
      ++r.frames_curved;
      ok = false;
    }
    if (last_lane >= 0) {
      const MountFrame& p = frames[static_cast<std::size_t>(last_lane)];
      const double dt = seconds(f.t_ns - p.t_ns);
      const double jump = f.lateral_offset_mm - p.lateral_offset_mm;
      // The own lane's centre jumps by about a lane width when the vehicle crosses a line.
      if (std::abs(jump) > 0.5 * f.lane_width_mm) {
        lane_change_t.push_back(seconds(f.t_ns));
        window_start = static_cast<int>(i);
      } else {
        // Moving sideways (changing lanes or swerving): the offset's change over the
        // window (since the last crossing or the first lane frame, when that is nearer,
        // over the whole window: a few frames' noise is no speed).
        while (seconds(f.t_ns - frames[static_cast<std::size_t>(window_start)].t_ns) > o.lateral_speed_window_s) {
          ++window_start;
          while (!frames[static_cast<std::size_t>(window_start)].lane) ++window_start;
        }
        const MountFrame& w = frames[static_cast<std::size_t>(window_start)];
        const double span = std::max(seconds(f.t_ns - w.t_ns), o.lateral_speed_window_s);
        if (std::abs(f.lateral_offset_mm - w.lateral_offset_mm) / span > o.max_lateral_speed_mm_s) {
          ++r.frames_lane_change;
          ok = false;
        }
      }
      if (ok && f.gyro_yaw_deg && p.gyro_yaw_deg && dt > 0.0 &&
          std::abs(wrap_deg(*f.gyro_yaw_deg - *p.gyro_yaw_deg)) / dt > o.max_yaw_rate_deg_s) {
        ++r.frames_turning;
        ok = false;
      }
    }
    keep[i] = ok;
    if (last_lane < 0) window_start = static_cast<int>(i);
    last_lane = static_cast<int>(i);
  }
  return keep;
}

// Drops the frames within lane_change_guard_s of a line crossing.
void drop_lane_changes(std::span<const MountFrame> frames, const std::vector<double>& lane_change_t,
                       const MountOptions& o, std::vector<bool>& keep, MountCalibration& r) {
  for (std::size_t i = 0; i < frames.size(); ++i) {
    if (!keep[i]) continue;
    const double t = seconds(frames[i].t_ns);
    for (double c : lane_change_t)
      if (std::abs(t - c) < o.lane_change_guard_s) {
        keep[i] = false;
        ++r.frames_lane_change;
        break;
      }
  }
}

// Per block, the sums (then means) of the kept frames' values; and the frames' variances
// summed.
struct Blocks {
  std::vector<double> psi, theta, phi, width;
  std::vector<int> frames, phi_frames;
  double var_psi = 0.0, var_theta = 0.0, var_width = 0.0;

  void add(std::size_t count) {
    for (std::size_t b = 0; b < count; ++b) {
      psi.push_back(0.0), theta.push_back(0.0), phi.push_back(0.0), width.push_back(0.0);
      frames.push_back(0);
      phi_frames.push_back(0);
    }
  }
  // One kept frame into block b.
  void add_frame(std::size_t b, const MountFrame& f) {
    psi[b] += f.psi_deg, theta[b] += f.theta_deg, width[b] += f.lane_width_mm;
    ++frames[b];
    if (f.phi_deg) phi[b] += *f.phi_deg, ++phi_frames[b];
    var_psi += f.sigma_psi_deg * f.sigma_psi_deg;
    var_theta += f.sigma_theta_deg * f.sigma_theta_deg;
    var_width += f.sigma_lane_width_mm * f.sigma_lane_width_mm;
  }
  // Empty blocks (a stretch with uneven frame times) carry nothing.
  void drop_empty() {
    for (std::size_t b = frames.size(); b-- > 0;)
      if (frames[b] == 0) {
        for (auto* v : {&psi, &theta, &phi, &width}) v->erase(v->begin() + static_cast<std::ptrdiff_t>(b));
        for (auto* v : {&frames, &phi_frames}) v->erase(v->begin() + static_cast<std::ptrdiff_t>(b));
      }
  }
};

// One stretch, frames[i, end), cut into equal blocks of at least block_s.
void add_stretch(std::span<const MountFrame> frames, std::size_t i, std::size_t end, double block_s, Blocks& blocks,
                 MountCalibration& r) {
  const std::size_t count = end - i;
  // A stretch lasts from its first frame to one frame interval past its last.
  const double t0 = seconds(frames[i].t_ns);
  const double span = seconds(frames[end - 1].t_ns - frames[i].t_ns);
  const double duration = count > 1 ? span * static_cast<double>(count) / static_cast<double>(count - 1) : 0.0;
  if (duration < block_s) return;
  ++r.stretches;
  r.straight_s += duration;
  const int n = std::max(1, static_cast<int>(std::floor(duration / block_s)));
  const std::size_t first_block = blocks.frames.size();
  blocks.add(static_cast<std::size_t>(n));
  for (std::size_t k = i; k < end; ++k) {
    const MountFrame& f = frames[k];
    const double t = seconds(f.t_ns) - t0;
    blocks.add_frame(first_block + static_cast<std::size_t>(std::min(n - 1, static_cast<int>(t / (duration / n)))), f);
    ++r.frames_kept;
  }
}

// Stretches: kept frames without a long gap between them (a frame now and then without
// lines, or left out, does not end one); each cut into equal blocks.
Blocks straight_blocks(std::span<const MountFrame> frames, const std::vector<bool>& keep, const MountOptions& o,
                       MountCalibration& r) {
  std::vector<MountFrame> kept;
  for (std::size_t i = 0; i < frames.size(); ++i)
    if (keep[i]) kept.push_back(frames[i]);
  Blocks blocks;
  const std::size_t n = kept.size();
  for (std::size_t i = 0; i < n;) {
    std::size_t end = i + 1;
    while (end < n && seconds(kept[end].t_ns - kept[end - 1].t_ns) <= o.max_gap_s) ++end;
    add_stretch(kept, i, end, o.block_s, blocks, r);
    i = end;
  }
  blocks.drop_empty();
  return blocks;
}

// Stills: every still kept is a block of its own (they are independent samples).
Blocks still_blocks(std::span<const MountFrame> frames, const MountOptions& o, MountCalibration& r) {
  Blocks blocks;
  for (const MountFrame& f : frames) {
    if (!f.lane) continue;
    ++r.frames_with_lane;
    if (on_bend(f, o)) {
      ++r.frames_curved;
      continue;
    }
    blocks.add(1);
    blocks.add_frame(blocks.frames.size() - 1, f);
    ++r.frames_kept;
  }
  return blocks;
}

// Why the drive gives no calibration, when it is too little: the status and message.
bool too_little(const MountOptions& o, MountCalibration& r) {
  if (o.stills ? r.frames_kept >= std::max(o.min_stills, kMinBlocks)
               : r.straight_s >= o.min_straight_s && r.blocks >= kMinBlocks)
    return false;
  char text[256];
  if (r.frames_with_lane == 0) {
    r.status = MountStatus::no_lines;
    std::snprintf(text, sizeof text, "none of the %d frames shows lane lines on both sides of the vehicle", r.frames);
  } else if (2 * r.frames_curved >= r.frames_with_lane) {
    r.status = MountStatus::only_curves;
    std::snprintf(text, sizeof text,
                  "%d of the %d frames with lane lines are on bends (radius under %.0f m): a bend's heading is "
                  "not the road's direction; drive a straight road",
                  r.frames_curved, r.frames_with_lane, o.min_radius_m);
  } else if (o.stills) {
    r.status = MountStatus::too_short;
    std::snprintf(text, sizeof text, "only %d of the %d stills show lane lines on both sides on a straight road, at least %d needed",
                  r.frames_kept, r.frames, std::max(o.min_stills, kMinBlocks));
  } else {
    r.status = MountStatus::too_short;
    std::snprintf(text, sizeof text,
                  "only %.1f s of straight driving with lines on both sides (%d frames kept of %d), at least "
                  "%.1f s needed",
                  r.straight_s, r.frames_kept, r.frames, o.min_straight_s);
  }
  r.message = text;
  return true;
}

}  // namespace

MountCalibration calibrate_mount(std::span<const MountFrame> frames, const MountOptions& o, double reference_phi_deg) {
  MountCalibration r;
  r.frames = static_cast<int>(frames.size());
  Blocks blocks;
  if (o.stills) {
    blocks = still_blocks(frames, o, r);
  } else {
    std::vector<double> lane_change_t;
    std::vector<bool> keep = straight_frames(frames, o, r, lane_change_t);
    drop_lane_changes(frames, lane_change_t, o, keep, r);
    blocks = straight_blocks(frames, keep, o, r);
  }

  // Roll from the blocks that saw three lines often enough to count.
  std::vector<double> phi_means;
  std::vector<int> phi_counts;
  int phi_total = 0;
  for (std::size_t b = 0; b < blocks.frames.size(); ++b) {
    const int count = blocks.frames[b];
    blocks.psi[b] /= count, blocks.theta[b] /= count, blocks.width[b] /= count;
    if (2 * blocks.phi_frames[b] >= count) {
      phi_means.push_back(blocks.phi[b] / blocks.phi_frames[b]);
      phi_counts.push_back(blocks.phi_frames[b]);
      phi_total += blocks.phi_frames[b];
    }
  }
  r.blocks = static_cast<int>(blocks.frames.size());
  if (too_little(o, r)) return r;

  const Mean mpsi = block_mean(blocks.psi, blocks.frames, blocks.var_psi, r.frames_kept);
  const Mean mtheta = block_mean(blocks.theta, blocks.frames, blocks.var_theta, r.frames_kept);
  const Mean mwidth = block_mean(blocks.width, blocks.frames, blocks.var_width, r.frames_kept);
  r.psi_deg = mpsi.value, r.sigma_psi_deg = mpsi.sigma;
  r.theta_deg = mtheta.value, r.sigma_theta_deg = mtheta.sigma;
  r.phi_determined = phi_means.size() >= kMinBlocks;
  if (r.phi_determined) {
    const Mean mphi = block_mean(phi_means, phi_counts, 0.0, phi_total);
    r.phi_deg = mphi.value, r.sigma_phi_deg = mphi.sigma;
  } else {
    r.phi_deg = reference_phi_deg;
  }
  r.measured_width_mm = mwidth.value, r.sigma_measured_width_mm = mwidth.sigma;
  // With the angles fixed, the road seen scales with H: a lane measured too wide at the
  // nominal H means the camera sits higher than that.
  r.H_mm = o.nominal_H_mm * o.lane_width_mm.mean / mwidth.value;
  const double rel_prior = o.lane_width_mm.sigma / o.lane_width_mm.mean;
  const double rel_measured = mwidth.sigma / mwidth.value;
  r.sigma_H_mm = r.H_mm * std::hypot(rel_prior, rel_measured);
  r.status = MountStatus::ok;
  return r;
}

const char* to_string(MountStatus status) {
  switch (status) {
    case MountStatus::ok: return "ok";
    case MountStatus::no_lines: return "no_lines";
    case MountStatus::only_curves: return "only_curves";
    case MountStatus::too_short: return "too_short";
  }
  return "unknown";
}

}  // namespace ccdlane::calibration
