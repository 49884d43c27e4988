// `ccdlane calibrate mount`: the camera's yaw, pitch, roll and height on the vehicle from
// a recorded drive, written as the configuration's [mount] and [attitude] tables.
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <vector>

#include "app/config_loader.hpp"
#include "app/frame_inputs.hpp"
#include "base/image_buffer.hpp"
#include "bus/channels.hpp"
#include "bus/frame_log.hpp"
#include "core/calibration/mount_calibration.hpp"
#include "drivers/frames/frame_directory.hpp"
#include "tools/ccdlane/calibration_output.hpp"
#include "tools/ccdlane/checked_output.hpp"
#include "tools/ccdlane/command.hpp"
#include "tools/ccdlane/video_recording.hpp"

namespace ccdlane::cli {
namespace {

using calibration::MountCalibration;
using calibration::MountFrame;
using calibration::MountOptions;
using calibration::MountStatus;

struct MountArgs {
  std::string config;
  std::string recording;
  std::string out;
  double lane_width_mm = 0.0;  // 0: the [prior] lane width, else 3.6 +- 0.2 m
  bool stills = false;         // every frame alone (a benchmark's pictures)
};

// One pass over the recording: every frame solved with roll fixed at phi_deg.
std::vector<MountFrame> solve_recording(const MountArgs& args, const Config& config, double phi_deg) {
  const int W = config.camera.Nu, H = config.camera.Nv;
  LaneEstimator estimator(calibration::mount_estimator_options(config.estimator_options(), phi_deg));
  std::vector<MountFrame> frames;
  const auto one = [&](const ImageView& image, const FrameMeta& recorded) {
    // The picture and its time only: the gyro only for the turn rate (as a prior it would
    // pull pitch towards its own), and the solves are judged at [vehicle] speed_kmh.
    FrameMeta meta;
    meta.sequence = recorded.sequence;
    meta.t_ns = recorded.t_ns;
    if (args.stills) estimator.reset();
    const LaneEstimate& e = estimator.estimate(frame_inputs(&image, meta.sequence, meta, {}, false));
    frames.push_back(calibration::mount_frame(e, estimator.solution(), recorded.gyro, phi_deg, config.H_mm));
  };
  try {
    if (is_video_recording(args.recording)) {
      const auto video = open_video_recording(args.recording, config, args.config);
      const std::string problem =
          read_video_recording(*video, [&](const ImageView& image, std::uint64_t index, std::int64_t t_ns) {
            FrameMeta meta;
            meta.sequence = index;
            meta.t_ns = t_ns;
            one(image, meta);
          });
      if (!problem.empty()) throw UsageError(problem + "; nothing written");
    } else if (std::filesystem::is_regular_file(args.recording)) {
      FrameLogReader log(args.recording, channel_name(config.lcm.prefix, Channel::frames));
      for (FrameLogReader::Next n; (n = log.next()) != FrameLogReader::Next::end;) {
        const ImageView& image = log.image();
        if (n != FrameLogReader::Next::frame || image.width != W || image.height != H) continue;
        one(image, recorded_frame_meta(log.record()));
      }
    } else {
      FrameDirectory dir(args.recording);
      if (!dir.note().empty()) std::cerr << "ccdlane calibrate mount: " << dir.note() << '\n';
      const auto header = dir.probe_first();
      if (header && (header->width != W || header->height != H))
        throw UsageError(args.recording + ": frames are " + std::to_string(header->width) + "x" +
                         std::to_string(header->height) + ", the camera of " + args.config + " is " +
                         std::to_string(W) + "x" + std::to_string(H));
      const PixelFormat format = header ? header->format() : PixelFormat::mono8;
      const ImageBuffer buffer(W, H, format, header && format == PixelFormat::mono16 ? header->significant_bits() : 8);
      for (std::size_t i = 0; i < dir.size(); ++i)
        if (dir.read(i, buffer.view()) == PgmFault::none) one(buffer.view(), recorded_frame_meta(dir.row(i)));
    }
  } catch (const UsageError&) {
    throw;
  } catch (const std::runtime_error& e) {  // FrameDirectoryError, FrameLogError
    throw UsageError(e.what());
  }
  return frames;
}

std::string mount_tables(const MountCalibration& m, const Config& config, const MountOptions& o) {
  std::ostringstream t;
  if (o.stills)
    t << "# ccdlane calibrate mount: " << m.frames_kept << " of " << m.frames
      << " stills, each solved alone; sigmas in the comments\n";
  else
    t << "# ccdlane calibrate mount: " << fixed(m.straight_s, 1) << " s of straight driving in " << m.stretches
      << " stretches (" << m.frames_kept << " of " << m.frames << " frames); sigmas in the comments\n";
  t
    << "[mount]\n"
    << "H_mm = " << toml_float(m.H_mm) << "  # sigma " << toml_float(m.sigma_H_mm) << "; lane measured "
    << fixed(m.measured_width_mm, 0) << " +/- " << fixed(m.sigma_measured_width_mm, 0) << " mm wide at H "
    << toml_float(config.H_mm) << ", taken as " << fixed(o.lane_width_mm.mean, 0)
    << (o.lane_width_mm.sigma > 0.0 ? " +/- " + fixed(o.lane_width_mm.sigma, 0) + " (prior)" : std::string(" (known)"))
    << "\n"
    << "[attitude]\n"
    << "psi_deg = " << toml_float(m.psi_deg) << "  # sigma " << toml_float(m.sigma_psi_deg) << "\n"
    << "theta_deg = " << toml_float(m.theta_deg) << "  # sigma " << toml_float(m.sigma_theta_deg)
    << "; includes the road's mean grade over the drive\n";
  if (m.phi_determined)
    t << "phi_deg = " << toml_float(m.phi_deg) << "  # sigma " << toml_float(m.sigma_phi_deg)
      << "; from equal lane widths, includes the road's mean crossfall\n";
  else
    t << "phi_deg = " << toml_float(m.phi_deg)
      << "  # not determined (never three lines in view): the configured roll\n";
  return t.str();
}

int run_mount(const MountArgs& args) {
  const Config config = load_config_file(args.config);
  MountOptions o;
  o.nominal_H_mm = config.H_mm;
  o.stills = args.stills;
  if (args.lane_width_mm > 0.0)
    o.lane_width_mm = {args.lane_width_mm, 0.0};
  else if (config.prior.lane_width_mm)
    o.lane_width_mm = *config.prior.lane_width_mm;
  const MountCalibration m = calibration::run_mount_passes(
      [&](double phi_deg) { return solve_recording(args, config, phi_deg); }, config.attitude.phi_deg, o);
  std::cerr << (o.stills ? "stills " : "frames ") << m.frames << ", with lane lines on both sides "
            << m.frames_with_lane << ", on bends " << m.frames_curved;
  if (!o.stills) std::cerr << ", turning " << m.frames_turning << ", changing lanes " << m.frames_lane_change;
  std::cerr << ", " << (o.stills ? "used " : "kept ") << m.frames_kept << "\n";
  if (m.status != MountStatus::ok)
    throw UsageError(args.recording + ": cannot calibrate the mount (" + calibration::to_string(m.status) +
                     "): " + m.message + "; nothing written");
  std::cerr << "psi   = " << fixed(m.psi_deg, 3) << " +/- " << fixed(m.sigma_psi_deg, 3) << " deg (configured "
            << fixed(config.attitude.psi_deg, 3) << ")\n"
            << "theta = " << fixed(m.theta_deg, 3) << " +/- " << fixed(m.sigma_theta_deg, 3) << " deg (configured "
            << fixed(config.attitude.theta_deg, 3) << ")\n"
            << "phi   = " << fixed(m.phi_deg, 3)
            << (m.phi_determined ? " +/- " + fixed(m.sigma_phi_deg, 3) : std::string(" not determined"))
            << " deg (configured " << fixed(config.attitude.phi_deg, 3) << ")\n"
            << "H     = " << fixed(m.H_mm, 0) << " +/- " << fixed(m.sigma_H_mm, 0) << " mm (configured "
            << fixed(config.H_mm, 0) << ")\n";
  const std::string tables = mount_tables(m, config, o);
  if (args.out.empty()) {
    std::cout << tables;
  } else {
    write_file_checked(args.out, tables);
    std::cerr << "wrote [mount] and [attitude] to " << args.out << "\n";
  }
  return 0;
}

}  // namespace

CommandAction setup_calibrate_mount(CLI::App& sub) {
  auto args = std::make_shared<MountArgs>();
  sub.add_option("config", args->config, "configuration (TOML) with the nominal mount and the camera")->required();
  sub.add_option(
         "recording", args->recording,
         "frame directory (frames.csv + PGM frames), LCM log of ccdlane.frame_t, or video file (.mp4, .mkv, .mov, "
         ".avi), of a drive on a marked road")
      ->required();
  sub.add_option("--out", args->out,
                 "write the [mount] and [attitude] tables here (atomically) instead of standard output");
  // A road's lanes are 2 to 5 m wide; 1e308 once wrote H_mm = inf, and -5, 0, NaN were
  // ignored in silence.
  sub.add_option("--lane-width-mm", args->lane_width_mm,
                 "the road's true lane width, if known (else [prior] lane_width_mm, else 3600 +/- 200)")
      ->check(number_from_to(2000.0, 5000.0));
  sub.add_flag("--stills", args->stills,
               "every frame on its own (pictures of one camera from unrelated clips, such as a benchmark's): "
               "each still with lines on both sides is one sample, at least 10 needed");
  sub.footer(
      "Solves every frame with H and roll fixed at the configured values, keeps straight stretches (no bend, no "
      "gyro turn, no lane change) with lines on both sides, and averages: yaw and pitch from the solves, roll from "
      "equal lane widths (three or more lines), H from the lane width measured against the true one. Sigmas from "
      "the spread of 1 s blocks (of the stills, with --stills). A recording too short, without lines or only on bends is refused (exit 2), and "
      "nothing is written.");
  return [args] { return run_mount(*args); };
}

}  // namespace ccdlane::cli
