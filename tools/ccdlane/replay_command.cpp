// `ccdlane replay`: the full per-frame pipeline over a recorded frame directory, an LCM
// log of frames or a video file, as fast as the machine allows, one JSON object per frame.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>
#include <vector>

#include "app/config_loader.hpp"
#include "base/image_buffer.hpp"
#include "bus/channels.hpp"
#include "bus/frame_log.hpp"
#include "core/lane/lane_estimator.hpp"
#include "drivers/frames/frame_directory.hpp"
#include "tools/ccdlane/checked_output.hpp"
#include "tools/ccdlane/command.hpp"
#include "tools/ccdlane/lane_estimate_json.hpp"
#include "tools/ccdlane/overlay_png.hpp"
#include "tools/ccdlane/overlay_video.hpp"
#include "tools/ccdlane/video_recording.hpp"

namespace ccdlane::cli {
namespace {

struct ReplayArgs {
  std::string config;
  std::string input;
  std::string out;
  std::string overlay;
  std::string overlay_video;
  bool sigmas = false;
};

void draw_overlay(const std::string& path, const ImageView& frame, const LaneEstimator& estimator,
                  const Config& config) {
  Overlay o(frame);
  const DetectionResult& d = estimator.detection();
  o.draw_marks(d.marks);
  if (const SolveResult* s = estimator.solution(); s && s->converged) {
    const CameraModel camera(config.camera, s->pose);
    for (int j = 0; j < s->num_lines; ++j) {
      const LaneLine& l = s->lines[static_cast<std::size_t>(j)];
      o.draw_road_line(camera, {l.y0_mm, l.m, l.c_per_mm}, config.detection.min_range_mm, config.detection.max_range_mm,
                       j);
    }
    o.draw_picks(estimator.solved_picks());
  } else {
    const CameraModel camera(config.camera, estimator.detection_pose());
    for (int j = 0; j < d.num_lines; ++j)
      o.draw_road_line(camera, d.lines[static_cast<std::size_t>(j)].fit, d.lines[static_cast<std::size_t>(j)].near_mm,
                       d.lines[static_cast<std::size_t>(j)].far_mm, j);
    o.draw_picks(d.picks);
  }
  o.write_png(path);
}

// The rows detection searched: between the road at max_range and at min_range straight
// ahead at the detection pose, less [detection] roi_top_px and hood_px (0-based).
std::pair<int, int> searched_rows(const ImageView& frame, const LaneEstimator& estimator, const Config& config) {
  const CameraModel camera(config.camera, estimator.detection_pose());
  const auto far = camera.pixel_from_point(Vec3(config.detection.max_range_mm, 0.0, 0.0));
  const auto near = camera.pixel_from_point(Vec3(config.detection.min_range_mm, 0.0, 0.0));
  int first = far ? static_cast<int>(std::floor(far->y() - 1.0)) : 0;
  int last = near ? static_cast<int>(std::ceil(near->y() - 1.0)) : frame.height - 1;
  first = std::max(first, config.detection.roi_top_px);
  last = std::min(last, frame.height - 1 - config.detection.hood_px);
  return {first, last};
}

}  // namespace

CommandAction setup_replay(CLI::App& sub) {
  auto a = std::make_shared<ReplayArgs>();
  sub.add_option("config", a->config, "configuration file (TOML)")->required();
  sub.add_option(
         "input", a->input,
         "frame directory (frames.csv + PGM, PPM or PNG frames), or an LCM log of ccdlane.frame_t on <[lcm] "
         "prefix>FRAMES "
         "(ccdlane record, or lcm-logger on a ccdlaned with [lcm] publish_frames), or a video file (.mp4, .mkv, "
         ".mov, .avi; H.264, H.265 or MJPEG) of [camera] Nu x Nv, its frame times from the container")
      ->required();
  sub.add_option("--out", a->out, "write the JSON Lines here instead of stdout");
  sub.add_option("--overlay", a->overlay,
                 "write here, per frame, a PNG with the marks, picks and fitted lines (NNNNNN.png) and one of the "
                 "lane-paint measure detection scanned (NNNNNN-paint.png)");
  sub.add_option("--overlay-video", a->overlay_video,
                 "write an annotated video here (H.264; .mp4, .mkv, .mov): each frame at its own time with the lines "
                 "found, the own lane filled, the candidate marks faint, a strip with width, offset, heading, radius, "
                 "state and LDW availability, and a departure warning on its side while it is held");
  sub.add_flag("--sigmas", a->sigmas, "add the solver's standard deviations to each object (\"sigma\")");
  sub.footer(
      "Runs detect -> solve (gyro roll/pitch from frames.csv as priors) -> track -> lane metrics on every "
      "frame, printing one JSON object per frame (docs/interfaces.md); from an LCM log, the gyro reading and "
      "timestamp each frame_t carries, other channels ignored; from a video, no gyro and [vehicle] speed_kmh. A "
      "damaged or cut video, or one whose times go backwards, exits 2 after the frames before it are written. "
      "Damaged frames are reported once each "
      "on stderr, counted, and give {\"ok\": false, \"reason\": \"no_frame\"}; a summary goes to stderr.");
  return [a] {
    const Config config = load_config_file(a->config);
    const int W = config.camera.Nu, H = config.camera.Nv;
    const bool is_video = is_video_recording(a->input);
    const bool is_log = !is_video && std::filesystem::is_regular_file(a->input);
    std::optional<FrameDirectory> dir;
    std::optional<FrameLogReader> log;
    std::unique_ptr<VideoReader> video;
    try {
      if (is_video)
        video = open_video_recording(a->input, config, a->config);
      else if (is_log)
        log.emplace(a->input, channel_name(config.lcm.prefix, Channel::frames));
      else
        dir.emplace(a->input);
    } catch (const std::runtime_error& e) {  // FrameDirectoryError, FrameLogError
      throw UsageError(e.what());
    }
    // The picture size is the camera's, from the configuration; a frame of another size is
    // skipped and counted wherever it is, the first one included. The first readable
    // frame gives only the pixel format.
    const auto header = dir ? dir->probe_first() : std::nullopt;
    const PixelFormat format = header ? header->format() : PixelFormat::mono8;
    const int bits = header && format == PixelFormat::mono16 ? header->significant_bits() : 8;

    std::unique_ptr<OutputFile> file;
    // The output must not replace the input: its frames.csv, or the log itself.
    if (!a->out.empty()) {
      std::error_code ec;
      const std::string input_file = is_log || is_video ? a->input : a->input + "/frames.csv";
      if (std::filesystem::equivalent(a->out, input_file, ec))
        throw UsageError(a->out + ": is the input being replayed (" + input_file + "); choose another --out");
    }
    if (!a->out.empty()) {
      try {
        file = std::make_unique<OutputFile>(a->out);
      } catch (const std::runtime_error& e) {
        throw UsageError(e.what());
      }
    }
    std::ostream& out = file ? file->stream() : std::cout;
    const std::string out_name = file ? a->out : "standard output";
    if (!a->overlay.empty()) {
      std::error_code ec;
      std::filesystem::create_directories(a->overlay, ec);
      if (ec) throw UsageError(a->overlay + ": cannot create the overlay directory: " + ec.message());
    }

    std::unique_ptr<OverlayVideo> overlay_video;
    if (!a->overlay_video.empty()) {
      try {  // in the input video's time base, so that the frames keep their times exactly
        overlay_video = std::make_unique<OverlayVideo>(a->overlay_video, W, H, video ? video->time_base_num() : 1,
                                                       video ? video->time_base_den() : 90'000);
      } catch (const std::runtime_error& e) {
        throw UsageError(e.what());
      }
    }

    const std::size_t csv_issues = dir ? dir->issues().size() : 0;  // malformed rows of frames.csv
    if (dir)
      for (const std::string& issue : dir->issues()) std::cerr << "ccdlane replay: " << issue << '\n';
    std::size_t skipped = csv_issues;

    const LaneEstimatorOptions options = config.estimator_options();
    LaneEstimator estimator(options);
    std::size_t frames = 0, ok = 0, overlays = 0;
    double total_s = 0.0, worst_s = 0.0;
    std::uint64_t worst_frame = 0;
    // One frame through the pipeline; `image` null for a frame that could not be read.
    bool observability_checked = false;
    const auto replay_frame = [&](const ImageView* image, std::uint64_t index, std::int64_t t_ns,
                                  const std::optional<Gx1Angles>& gyro, const VehicleInputs& vehicle) {
      // As the daemon does at start: refuse solves that cannot determine what they are
      // asked for. The roll is measured when the recording's first readable frame carries
      // a gyro reading, or when it was made with a gyro (whose first readings may come
      // after the first frames), as the daemon counts a configured gyro.
      if (image && !observability_checked && (observability_checked = true))
        if (const std::string why = observability_problem(options, gyro || !config.gyro.device.empty()); !why.empty())
          throw UsageError(a->config + ": " + why + " (the frames of " + a->input + " carry " + (gyro ? "" : "no ") +
                           "gyro readings)");
      ++frames;
      if (!image) {
        ++skipped;
        print_json_line(out, lane_estimate_json(estimator.no_frame(index, t_ns, vehicle), a->sigmas));
        check_written(out, out_name);
        return;
      }
      const auto t0 = std::chrono::steady_clock::now();
      LaneEstimate e = estimator.estimate(*image, index, t_ns, gyro, vehicle);
      const double dt = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      e.latency_us = static_cast<std::int64_t>(dt * 1e6);
      total_s += dt;
      if (dt > worst_s) worst_s = dt, worst_frame = index;
      ok += e.ok;
      print_json_line(out, lane_estimate_json(e, a->sigmas));
      check_written(out, out_name);
      if (overlay_video) overlay_video->add(*image, e, estimator, config);
      if (!a->overlay.empty()) {
        char name[32], paint[32];
        std::snprintf(name, sizeof name, "/%06llu.png", static_cast<unsigned long long>(index));
        std::snprintf(paint, sizeof paint, "/%06llu-paint.png", static_cast<unsigned long long>(index));
        try {
          draw_overlay(a->overlay + name, *image, estimator, config);
          const auto [first, last] = searched_rows(*image, estimator, config);
          write_paint_measure_png(a->overlay + paint, *image, first, last);
        } catch (const std::runtime_error& failure) {
          // Each PNG is whole or absent (temporary name, then rename): say what is there.
          throw std::runtime_error(std::string(failure.what()) + "; " + std::to_string(overlays) +
                                   " complete overlays remain in " + a->overlay + ", no partial file");
        }
        ++overlays;
      }
    };

    std::string video_problem;  // a damaged, cut or mistimed video: said after the output is kept
    if (dir) {
      const ImageBuffer buffer(W, H, format, bits);
      const MutableImageView& image = buffer.view();
      for (std::size_t i = 0; i < dir->size(); ++i) {
        const FrameRow& row = dir->row(i);
        const bool read = dir->read(i, image) == PgmFault::none;
        if (!read) std::cerr << "ccdlane replay: " << dir->error() << '\n';
        const ImageView view = image;
        VehicleInputs vehicle;  // without the columns: [vehicle] speed_kmh, no indicator
        if (row.speed_kmh) vehicle.speed_mps = *row.speed_kmh / 3.6;
        vehicle.indicator = row.indicator;
        vehicle.gyro_ok = row.gyro || config.gyro.device.empty();  // as ccdlaned playing the directory
        replay_frame(read ? &view : nullptr, row.index, row.t_ns, row.gyro, vehicle);
      }
    } else if (video) {
      // A dashcam records no gyro, speed or indicator: [vehicle] speed_kmh, no indicator.
      VehicleInputs vehicle;
      vehicle.gyro_ok = config.gyro.device.empty();
      video_problem = read_video_recording(*video, [&](const ImageView& image, std::uint64_t index, std::int64_t t_ns) {
        replay_frame(&image, index, t_ns, std::nullopt, vehicle);
      });
    } else {
      for (FrameLogReader::Next n; (n = log->next()) != FrameLogReader::Next::end;) {
        if (n == FrameLogReader::Next::lost) {  // no frame to print: its number is unknown
          std::cerr << "ccdlane replay: " << log->problem() << '\n';
          continue;
        }
        const FrameRecord& r = log->record();
        const ImageView& image = log->image();
        bool usable = n == FrameLogReader::Next::frame;
        if (!usable) {
          std::cerr << "ccdlane replay: " << log->problem() << '\n';
        } else if (image.width != W || image.height != H) {
          std::cerr << "ccdlane replay: " << a->input << ": frame " << r.sequence << " is " << image.width << "x"
                    << image.height << ", the camera of " << a->config << " is " << W << "x" << H << '\n';
          usable = false;
        }
        VehicleInputs vehicle;  // as the daemon had it when it recorded the frame
        if (r.speed_kmh) vehicle.speed_mps = *r.speed_kmh / 3.6;
        vehicle.yaw_rate_radps = r.yaw_rate_radps;
        vehicle.indicator = r.indicator;
        // As the daemon judged it: a configured gyro that gave the frame no reading failed.
        vehicle.gyro_ok = r.gyro || config.gyro.device.empty();
        replay_frame(usable ? &image : nullptr, r.sequence, r.t_ns, r.gyro, vehicle);
      }
      if (frames == 0 && log->lost_events() == 0)
        throw UsageError(a->input + ": no frames on channel " + log->channel() + " (" +
                         std::to_string(log->other_events()) + " events on other channels)");
    }
    const std::size_t processed = frames - (skipped - csv_issues);
    // Nothing replayed is bad input, not a result: no output file is left.
    if (((frames > 0 && processed == 0) || (video && frames == 0)) && file) file.reset();
    if (file)
      file->commit();
    else
      flush_checked(std::cout, "standard output");
    if (overlay_video && overlay_video->frames() > 0) {  // the frames before a damaged one are kept too
      overlay_video->finish();
      std::cerr << "ccdlane replay: " << overlay_video->frames() << " annotated frames in " << a->overlay_video << '\n';
    }
    char summary[256];
    std::snprintf(summary, sizeof summary,
                  "ccdlane replay: %zu frames, %zu ok, %zu skipped; per frame %.3f ms mean, %.3f ms worst (frame %llu)",
                  frames + csv_issues, ok, skipped, processed ? 1e3 * total_s / static_cast<double>(processed) : 0.0,
                  1e3 * worst_s, static_cast<unsigned long long>(worst_frame));
    std::cerr << summary << '\n';
    // Frames lost to a damaged or cut log are a failed replay even when the rest went
    // well: the output is kept, the status says it is incomplete.
    if (log && log->lost_events() > 0) {
      std::fprintf(stderr, "ccdlane replay: %s: %llu event(s) lost to damage (%llu bytes skipped)%s\n",
                   a->input.c_str(), static_cast<unsigned long long>(log->lost_events()),
                   static_cast<unsigned long long>(log->lost_bytes()),
                   log->truncated() ? ", the last one cut short" : "");
      return 1;
    }
    if (!video_problem.empty()) throw UsageError(video_problem);
    if (frames > 0 && processed == 0) throw UsageError(a->input + ": none of the frames could be read");
    return 0;
  };
}

}  // namespace ccdlane::cli
