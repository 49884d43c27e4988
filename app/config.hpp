// The validated ccdlane configuration (docs/interfaces.md "Configuration"): one schema
// for the daemon and every tool, made of the option structs of the layers below. Values
// are in the units of the file (mm, degrees).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "bus/lcm_publisher.hpp"
#include "core/lane/online_mount_refiner.hpp"
#include "core/detection/detection_config.hpp"
#include "core/geometry/attitude.hpp"
#include "core/geometry/camera_model.hpp"
#include "core/lane/lane_estimator.hpp"
#include "core/ldw/ldw_monitor.hpp"
#include "core/ldw/vehicle.hpp"
#include "core/solver/solver_options.hpp"
#include "core/synth/synth_config.hpp"

namespace ccdlane {

// [solver]: the solver's options and the picks file `ccdlane solve` reads.
struct SolverConfig : SolverOptions {
  std::string picks;  // optional picks file, resolved relative to the config file

  bool operator==(const SolverConfig&) const = default;
};

using PriorConfig = SolverPriors;  // [prior]

struct GyroConfig {
  double sigma_deg = 0.5;  // std. dev. of its roll and pitch, used as priors
  std::string device;      // "" = no gyro, "emulated", or a serial device path

  bool operator==(const GyroConfig&) const = default;
};

enum class SourceKind { synth, frames, v4l2, aravis, video };

// [source] pixel_format: what a v4l2 or aravis camera is asked to deliver.
enum class SourcePixels { automatic, grey, colour };

struct SourceConfig {
  SourceKind kind = SourceKind::synth;
  std::string device = "/dev/video0";
  std::string camera;
  std::string path;
  double rate_hz = 30.0;
  bool loop = false;
  SourcePixels pixel_format = SourcePixels::automatic;
  // An Aravis camera's own name of the pixel format to use ("BayerRG8"), among those
  // pixel_format allows; empty: the driver's preference (RGB8 before Bayer).
  std::string device_format;

  bool operator==(const SourceConfig&) const = default;
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

// [calibration]: ccdlaned's online refinement of the mount's yaw and pitch ([attitude]
// psi_deg and theta_deg stay the starting point and the centre of the bounds).
struct CalibrationConfig {
  bool online = false;
  double min_speed_kmh = 50.0;
  double min_radius_m = 500.0;  // road bends tighter than this are not used
  // A mount is known to a few degrees (the issue "Lanes on any road": 5): the learned
  // correction may reach that, with a degree of room for its spread.
  double max_correction_deg = 6.0;
  double max_change_deg_per_min = 0.5;
  int frames_needed = 900;
  std::string state_file;       // "" = mount-refinement.toml in $STATE_DIRECTORY (none: not kept)
  double save_period_s = 60.0;  // how often a changed estimate is written while running

  bool operator==(const CalibrationConfig&) const = default;
};

struct Config {
  std::string path;  // where it was loaded from ("" for built-in defaults)
  CameraSpec camera;
  double f_mm = 5.05;
  double H_mm = 1400.0;
  AttitudeDeg attitude;
  SolverConfig solver;
  PriorConfig prior;
  std::vector<RoadLine> lines;
  GyroConfig gyro;
  SourceConfig source;
  LcmConfig lcm;
  RealtimeConfig realtime;
  DaemonConfig daemon;
  SynthConfig synth;
  DetectionConfig detection;
  ldw::VehicleConfig vehicle;  // [vehicle]
  // [ldw]: the lane departure warning's tunables. Its own `vehicle` member is not read
  // from the file: estimator_options() fills it from [vehicle] above.
  ldw::LdwConfig ldw;
  CalibrationConfig calibration;

  // The nominal pose: [attitude] angles, [mount] H_mm, [camera] f_mm.
  CameraPose nominal_pose() const;
  // What the lane estimator needs of all this.
  LaneEstimatorOptions estimator_options() const;
  // What the online mount refiner needs: [calibration] around [attitude].
  calibration::OnlineMountOptions online_mount_options() const;
  bool operator==(const Config&) const = default;
};

// The reference camera of docs/geometry.md (DH-HV2003UC), used when no config is given.
Config default_config();

}  // namespace ccdlane
