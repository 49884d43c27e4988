// The validated ccdlane configuration (interfaces.md "Configuration"): one schema for the
// daemon and every tool. Values are in the units of the file (mm, degrees).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/config/detection_config.hpp"
#include "core/config/synth_config.hpp"
#include "core/geometry/camera_model.hpp"

namespace ccdlane {

// The unknowns a problem may leave free (solver.md "Unknowns").
enum class FreeParam : std::uint8_t { psi, theta, phi, H, f, y0, m, c };
constexpr int kFreeParamCount = 8;

class FreeSet {
 public:
  constexpr FreeSet() = default;
  constexpr bool has(FreeParam p) const { return (bits_ >> static_cast<int>(p)) & 1u; }
  constexpr void add(FreeParam p) { bits_ |= static_cast<std::uint8_t>(1u << static_cast<int>(p)); }
  constexpr void remove(FreeParam p) { bits_ &= static_cast<std::uint8_t>(~(1u << static_cast<int>(p))); }
  constexpr bool operator==(const FreeSet&) const = default;

 private:
  std::uint8_t bits_ = 0;
};

const char* free_param_name(FreeParam p);                 // "psi", "theta", ...
std::optional<FreeParam> free_param_from_name(const std::string& name);

enum class SolverMode { reprojection, paper };

// How the lane lines bend (geometry.md: y = y0_j + m_j x + c_j x^2).
enum class LineModel : std::uint8_t {
  // Each line its own y0, m and c, each kind free or fixed as the free set says: with c
  // fixed (the default free set, and fitted lines start at c = 0) the seed paper's
  // straight lines. Config: line_model = "straight".
  per_line,
  // The lines of one road are parallel curves: one curvature c shared by every line of
  // the frame, always free; y0 and m per line as the free set says (which must not hold
  // c). A straight model on a bend biases yaw by about c (x_near + x_far); this one does
  // not. c needs marks at three or more distances. Config: line_model = "curved".
  shared_curvature,
};

// A Gaussian prior N(mean, sigma^2) on one quantity, in the file's units.
struct Prior {
  double mean = 0.0;
  double sigma = 0.0;

  bool operator==(const Prior&) const = default;
};

struct AttitudeDeg {
  double psi_deg = 0.0;
  double theta_deg = 0.0;
  double phi_deg = 0.0;

  bool operator==(const AttitudeDeg&) const = default;
};

struct SolverConfig {
  SolverMode mode = SolverMode::reprojection;
  FreeSet free = default_free();
  LineModel line_model = LineModel::per_line;
  double pixel_sigma = 0.5;
  int max_iterations = 50;
  std::string picks;  // optional picks file, resolved relative to the config file

  static FreeSet default_free();
  bool operator==(const SolverConfig&) const = default;
};

struct PriorConfig {
  std::optional<Prior> psi_deg, theta_deg, phi_deg, H_mm, f_mm, lane_width_mm;

  bool operator==(const PriorConfig&) const = default;
};

struct LineInit {
  double y0_mm = 0.0;
  double m = 0.0;
  double c_per_mm = 0.0;

  bool operator==(const LineInit&) const = default;
};

struct GyroConfig {
  double sigma_deg = 0.5;  // std. dev. of its roll and pitch, used as priors
  std::string device;      // "" = no gyro, "emulated", or a serial device path

  bool operator==(const GyroConfig&) const = default;
};

enum class SourceKind { synth, frames, v4l2, aravis };

struct SourceConfig {
  SourceKind kind = SourceKind::synth;
  std::string device = "/dev/video0";
  std::string camera;
  std::string path;
  double rate_hz = 30.0;
  bool loop = false;

  bool operator==(const SourceConfig&) const = default;
};

struct LcmConfig {
  std::string url = "udpm://239.255.76.67:7667?ttl=0";
  std::string prefix = "CCDLANE_";
  bool publish_frames = false;  // raw frames on <prefix>FRAMES too, for lcm-logger (large: ~0.5 MB each)

  bool operator==(const LcmConfig&) const = default;
};

struct RealtimeConfig {
  bool mlock = false;
  int capture_priority = 0;
  int processing_priority = 0;
  int gyro_priority = 0;
  std::vector<int> cpus;  // affinity of every pipeline thread; empty = any CPU

  bool operator==(const RealtimeConfig&) const = default;
};

// ccdlaned's own knobs ([daemon]).
struct DaemonConfig {
  int queue_depth = 4;           // frames that may wait for processing; beyond, the oldest is dropped
  double stall_timeout_s = 2.0;  // no frame for this long: the camera is reported stalled

  bool operator==(const DaemonConfig&) const = default;
};

struct Config {
  std::string path;  // where it was loaded from ("" for built-in defaults)
  CameraSpec camera;
  double f_mm = 5.05;
  double H_mm = 1400.0;
  AttitudeDeg attitude;
  SolverConfig solver;
  PriorConfig prior;
  std::vector<LineInit> lines;
  GyroConfig gyro;
  SourceConfig source;
  LcmConfig lcm;
  RealtimeConfig realtime;
  DaemonConfig daemon;
  SynthConfig synth;
  DetectionConfig detection;

  // The nominal pose: [attitude] angles, [mount] H_mm, [camera] f_mm.
  CameraPose nominal_pose() const;
  bool operator==(const Config&) const = default;
};

// The reference camera of geometry.md (DH-HV2003UC), used when no config is given.
Config default_config();

}  // namespace ccdlane
