// `ccdlane synth`: render a frame directory of a synthetic road with its truth columns.
#include <chrono>
#include <cmath>
#include <iostream>
#include <memory>
#include <optional>
#include <vector>

#include "app/config_loader.hpp"
#include "base/image_buffer.hpp"
#include "core/synth/road_renderer.hpp"
#include "core/synth/synth_drive.hpp"
#include "drivers/frames/frame_directory_writer.hpp"
#include "tools/ccdlane/command.hpp"

namespace ccdlane::cli {
namespace {

struct SynthArgs {
  std::string config;
  std::string out;
  std::optional<int> frames, lanes, bits, cars;
  std::optional<std::uint64_t> seed;
  std::optional<double> noise, shadows, blur, curvature, lane_change_at, gyro_noise;
  bool no_gyro = false, night = false;
};

// The truth columns, in this order: attitude, lane, then every road line left to right.
std::vector<std::string> truth_columns(int num_lines) {
  std::vector<std::string> cols = {"truth_psi_deg",       "truth_theta_deg",         "truth_phi_deg",
                                   "truth_H_mm",          "truth_lateral_offset_mm", "truth_heading_deg",
                                   "truth_lane_width_mm", "truth_ego_lane",          "truth_c_per_mm"};
  for (int j = 0; j < num_lines; ++j) cols.push_back("truth_y0_" + std::to_string(j) + "_mm");
  return cols;
}

void truth_values(const SynthFrame& f, std::vector<double>& v) {
  v = {rad_to_deg(f.pose.attitude.psi),
       rad_to_deg(f.pose.attitude.theta),
       rad_to_deg(f.pose.attitude.phi),
       f.pose.H_mm,
       f.lateral_offset_mm,
       f.heading_deg,
       f.lane_width_mm,
       static_cast<double>(f.ego_lane),
       f.c_per_mm};
  for (int j = 0; j < f.num_lines; ++j) v.push_back(f.y0_mm[static_cast<std::size_t>(j)]);
}

}  // namespace

CommandAction setup_synth(CLI::App& sub) {
  auto a = std::make_shared<SynthArgs>();
  sub.add_option("config", a->config, "configuration file (TOML): [camera], [mount], [attitude], [synth]")->required();
  sub.add_option("--out", a->out, "frame directory to create (must not hold a frames.csv yet)")->required();
  sub.add_option("--frames", a->frames, "number of frames (default [synth] frames)")->check(CLI::Range(1, 1'000'000));
  sub.add_option("--seed", a->seed, "random seed (default [synth] seed)");
  sub.add_option("--noise", a->noise, "sensor noise sigma, grey levels")->check(CLI::Range(0.0, 100.0));
  sub.add_option("--shadows", a->shadows, "shadow depth 0..<1 (0 = none)")->check(CLI::Range(0.0, 0.95));
  sub.add_option("--blur", a->blur, "Gaussian blur sigma, pixels")->check(CLI::Range(0.0, 10.0));
  sub.add_option("--curvature", a->curvature, "lane curvature c, 1/mm (1/(2R))")->check(CLI::Range(-1e-5, 1e-5));
  sub.add_option("--lanes", a->lanes, "lanes on the road, 2..4")->check(CLI::Range(2, 4));
  sub.add_option("--lane-change-at", a->lane_change_at, "seconds into the drive to change to the right lane");
  sub.add_option("--bits", a->bits, "8 for mono8 frames, 9..16 for 16-bit PGM")->check(CLI::Range(8, 16));
  sub.add_option("--gyro-noise", a->gyro_noise, "noise on the gyro roll/pitch columns, degrees")
      ->check(CLI::Range(0.0, 10.0));
  sub.add_flag("--no-gyro", a->no_gyro, "leave out the roll_deg,pitch_deg,yaw_deg columns");
  sub.add_flag("--night", a->night, "the road lit by the car's low beams alone ([synth] night)");
  sub.add_option("--cars", a->cars, "cars: one ahead, one beside on each side, more farther on ([synth] cars)")
      ->check(CLI::Range(0, kMaxSynthCars));
  sub.footer(
      "Writes DIR/000000.pgm ... and DIR/frames.csv with file,t_ns, the gyro columns and truth_* "
      "columns (attitude, lateral offset, heading, lane width, ego lane, curvature, truth_y0_J_mm "
      "of every road line left to right). Nothing is left behind on failure.");
  return [a] {
    Config config = load_config_file(a->config);
    SynthConfig& s = config.synth;
    if (a->frames) s.frames = *a->frames;
    if (a->seed) s.seed = *a->seed;
    if (a->noise) s.noise_sigma = *a->noise;
    if (a->shadows) s.shadow_depth = *a->shadows;
    if (a->blur) s.blur_px = *a->blur;
    if (a->curvature) s.curvature_per_mm = *a->curvature;
    if (a->lanes) s.lanes = *a->lanes;
    if (a->lane_change_at) s.lane_change_at_s = *a->lane_change_at;
    if (a->bits) s.bits = *a->bits;
    if (a->gyro_noise) s.gyro_noise_deg = *a->gyro_noise;
    if (a->no_gyro) s.gyro = false;
    if (a->night) s.night = true;
    if (a->cars) s.cars = *a->cars;
    if (s.ego_lane >= s.lanes) s.ego_lane = s.lanes - 1;
    if (s.lane_change_at_s >= 0.0 && s.ego_lane + 1 >= s.lanes)
      throw UsageError("--lane-change-at: the vehicle is in the rightmost lane; there is no lane to change to");

    const SynthDrive drive(config.synth, config.nominal_pose());
    RoadRenderer renderer(config.camera, s);
    const int W = config.camera.Nu, H = config.camera.Nv;
    const PixelFormat format = renderer.format();
    const ImageBuffer buffer(W, H, format, s.bits);
    const MutableImageView& image = buffer.view();
    std::optional<FrameDirectoryWriter> writer;
    try {
      writer.emplace(a->out, FrameDirectoryLayout{s.gyro, truth_columns(drive.num_lines())});
    } catch (const FrameDirectoryError& e) {
      throw UsageError(e.what());
    }
    std::vector<double> truth;
    double render_s = 0.0;
    for (int k = 0; k < s.frames; ++k) {
      const SynthFrame f = drive.frame(static_cast<std::uint64_t>(k));
      const auto t0 = std::chrono::steady_clock::now();
      renderer.render(f, image);
      render_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      truth_values(f, truth);
      writer->write(image, f.t_ns, s.gyro ? std::optional<Gx1Angles>(f.gyro) : std::nullopt, truth);
    }
    writer->finish();
    std::cerr << "ccdlane synth: wrote " << s.frames << " frames of " << W << "x" << H << " ("
              << (format == PixelFormat::mono16 ? std::to_string(s.bits) + "-bit" : std::string("8-bit")) << ") to "
              << a->out << ", " << std::round(1e4 * render_s / s.frames) / 10.0 << " ms per frame to render\n";
    return 0;
  };
}

}  // namespace ccdlane::cli
