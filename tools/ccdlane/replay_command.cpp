// `ccdlane replay`: the full per-frame pipeline over a recorded frame directory or an LCM
// log of frames, as fast as the machine allows, one JSON object per frame.
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
#include "app/frame_inputs.hpp"
#include "base/image_buffer.hpp"
#include "base/output_path.hpp"
#include "bus/channels.hpp"
#include "bus/frame_log.hpp"
#include "core/lane/lane_estimator.hpp"
#include "core/lane/observability.hpp"
#include "drivers/frames/frame_directory.hpp"
#include "tools/ccdlane/checked_output.hpp"
#include "tools/ccdlane/command.hpp"
#include "tools/ccdlane/lane_estimate_json.hpp"
#include "tools/ccdlane/overlay_png.hpp"
#include "tools/ccdlane/overlay_video.hpp"
#include "tools/ccdlane/picture_condition.hpp"
#include "tools/ccdlane/video_recording.hpp"

namespace ccdlane::cli {
namespace {

struct ReplayArgs {
  std::string config;
  std::string input;
  std::string out;
  std::string overlay;
  std::string overlay_video;
  std::string condition;
  bool sigmas = false;
  bool stills = false;
};

void draw_overlay(const std::string& path, const ImageView& frame, const LaneEstimator& estimator,
                  const Config& config) {
  Overlay o(frame);
  if (const VanishingPoint* vp = estimator.vanishing_point()) o.draw_vanishing_point(*vp);
  const DetectionResult& d = estimator.detection();
  o.draw_marks(d.marks);
  if (const SolveResult* s = estimator.solution(); s && s->converged) {
    const CameraModel camera(config.camera, s->pose);
    for (int j = 0; j < s->num_lines; ++j) {
      o.draw_road_line(camera, s->lines[static_cast<std::size_t>(j)], config.detection.min_range_mm,
                       config.detection.max_range_mm, j);
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

// One replay: the input and output opened, every frame through the estimator, and the
// tallies the summary line gives.
class Replay {
 public:
  // Loads the configuration and opens the input, the output and the overlay directory;
  // UsageError for anything that is bad input.
  explicit Replay(const ReplayArgs& args);
  // Replays every frame; the exit status (1: events of the log were lost to damage).
  int run();

 private:
  void open_input();
  void open_output();
  void replay_directory();
  void replay_log();
  void replay_video();
  void replay_frame(const ImageView* image, const FrameMeta& meta);
  void check_observability(const FrameMeta& meta);
  void write_overlays(const ImageView& image, std::uint64_t index);
  int finish();

  const ReplayArgs& a_;
  const Config config_;               // the recorded frames' camera
  const PictureCondition condition_;  // --condition
  const Config seen_;                 // the camera the conditioned frames are from (scale)
  const LaneEstimatorOptions options_;
  const bool gyro_configured_;
  std::optional<FrameDirectory> dir_;
  std::optional<FrameLogReader> log_;
  std::unique_ptr<VideoReader> video_;
  std::string video_problem_;  // a damaged, cut or mistimed video: said after the output is kept
  // The first frame that could not be read, and why: said again when none could be, so
  // that the last line (what a script shows) names the cause, not only the count.
  std::string first_unread_;
  // "the camera of CONFIG is WxH": what a frame of another size is told.
  std::string camera_size() const {
    return "the camera of " + a_.config + " is " + std::to_string(config_.camera.Nu) + "x" +
           std::to_string(config_.camera.Nv);
  }
  std::unique_ptr<OverlayVideo> overlay_video_;
  PixelFormat format_ = PixelFormat::mono8;  // of a frame directory's frames
  int bits_ = 8;
  std::unique_ptr<OutputFile> file_;
  std::ostream* out_ = &std::cout;
  std::string out_name_ = "standard output";
  LaneEstimator estimator_;
  PictureConditioner conditioner_;
  bool observability_checked_ = false;
  std::size_t csv_issues_ = 0;  // malformed rows of frames.csv
  std::size_t frames_ = 0, ok_ = 0, skipped_ = 0, overlays_ = 0;
  double total_s_ = 0.0, worst_s_ = 0.0;
  std::uint64_t worst_frame_ = 0;
};

PictureCondition condition(const std::string& spec) {
  try {
    return parse_picture_condition(spec);
  } catch (const std::invalid_argument& bad) {
    throw UsageError(std::string("--condition ") + bad.what());
  }
}

// `config` as the camera that takes the conditioned pictures: its cells, and the rows
// detection never searches, in that camera's pixels. A picture resized up holds no more
// than the recorded one: its picks are as uncertain as the recorded ones' in angle, so
// more of its smaller pixels (the solver's pixel_sigma times the scale; left as it is in
// a picture resized down, whose pixels bound them). Taken at 0.5 px, the solve weighed
// its priors a third less against the picks and segA's offset moved twice as much from
// frame to frame (a median of 21.9 mm against 12.2; 12.2 with the sigma scaled).
Config config_taking(const Config& config, const PictureCondition& condition) {
  Config c = config;
  c.camera = camera_taking(condition, config.camera);
  const auto rows = [&](int n) { return static_cast<int>(std::lround(n * condition.scale)); };
  c.detection.roi_top_px = rows(config.detection.roi_top_px);
  c.detection.hood_px = rows(config.detection.hood_px);
  c.solver.pixel_sigma = config.solver.pixel_sigma * std::max(1.0, condition.scale);
  return c;
}

Replay::Replay(const ReplayArgs& args)
    : a_(args),
      config_(load_config_file(args.config)),
      condition_(condition(args.condition)),
      seen_(config_taking(config_, condition_)),
      options_(seen_.estimator_options()),
      gyro_configured_(!config_.gyro.device.empty()),
      estimator_(options_),
      conditioner_(condition_) {
  open_input();
  open_output();
}

void Replay::open_input() {
  try {
    if (is_video_recording(a_.input))
      video_ = open_video_recording(a_.input, config_, a_.config);
    else if (std::filesystem::is_regular_file(a_.input))
      log_.emplace(a_.input, channel_name(config_.lcm.prefix, Channel::frames));
    else
      dir_.emplace(a_.input);
  } catch (const std::runtime_error& e) {  // FrameDirectoryError, FrameLogError
    throw UsageError(e.what());
  }
  // The picture size is the camera's, from the configuration; a frame of another size is
  // skipped and counted wherever it is, the first one included. The first readable
  // frame gives only the pixel format.
  const auto header = dir_ ? dir_->probe_first() : std::nullopt;
  format_ = header ? header->format() : PixelFormat::mono8;
  bits_ = header && format_ == PixelFormat::mono16 ? header->significant_bits() : 8;
}

void Replay::open_output() {
  // The output must not replace the input: the log itself, or anything in the directory
  // (frames.csv, a frame; overlays written over colour PNG frames once destroyed them).
  for (const auto& [path, option] : {std::pair{a_.out, "--out"}, std::pair{a_.overlay, "--overlay"}})
    if (!path.empty() && lies_within(path, a_.input))
      throw UsageError(path + ": is or lies inside the input being replayed (" + a_.input + "); choose another " +
                       option);
  if (!a_.out.empty()) {
    try {
      file_ = std::make_unique<OutputFile>(a_.out);
    } catch (const std::runtime_error& e) {
      throw UsageError(e.what());
    }
    out_ = &file_->stream();
    out_name_ = a_.out;
  }
  if (!a_.overlay.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(a_.overlay, ec);
    if (ec) throw UsageError(a_.overlay + ": cannot create the overlay directory: " + ec.message());
  }
  if (!a_.overlay_video.empty()) {
    try {  // in the input video's time base, so that the frames keep their times exactly
      overlay_video_ = std::make_unique<OverlayVideo>(a_.overlay_video, seen_.camera.Nu, seen_.camera.Nv,
                                                      video_ ? video_->time_base_num() : 1,
                                                      video_ ? video_->time_base_den() : 90'000);
    } catch (const std::runtime_error& e) {
      throw UsageError(e.what());
    }
  }
}

int Replay::run() {
  if (dir_) {
    csv_issues_ = dir_->issues().size();
    for (const std::string& issue : dir_->issues()) std::cerr << "ccdlane replay: " << issue << '\n';
    if (!dir_->note().empty()) std::cerr << "ccdlane replay: " << dir_->note() << '\n';
    skipped_ = csv_issues_;
    replay_directory();
  } else if (video_) {
    replay_video();
  } else {
    replay_log();
  }
  return finish();
}

void Replay::replay_directory() {
  const ImageBuffer buffer(config_.camera.Nu, config_.camera.Nv, format_, bits_);
  const MutableImageView& image = buffer.view();
  for (std::size_t i = 0; i < dir_->size(); ++i) {
    const PgmFault fault = dir_->read(i, image);
    const bool read = fault == PgmFault::none;
    if (!read) std::cerr << "ccdlane replay: " << dir_->error() << '\n';
    if (!read && first_unread_.empty())
      first_unread_ = std::string(dir_->error()) +
                      (fault == PgmFault::wrong_size ? ", " + camera_size() + " ([camera] Nu, Nv)" : std::string());
    const ImageView view = image;
    replay_frame(read ? &view : nullptr, recorded_frame_meta(dir_->row(i)));
  }
}

void Replay::replay_log() {
  const int W = config_.camera.Nu, H = config_.camera.Nv;
  for (FrameLogReader::Next n; (n = log_->next()) != FrameLogReader::Next::end;) {
    if (n == FrameLogReader::Next::lost) {  // no frame to print: its number is unknown
      std::cerr << "ccdlane replay: " << log_->problem() << '\n';
      continue;
    }
    const FrameRecord& r = log_->record();
    const ImageView& image = log_->image();
    bool usable = n == FrameLogReader::Next::frame;
    if (!usable) {
      std::cerr << "ccdlane replay: " << log_->problem() << '\n';
    } else if (image.width != W || image.height != H) {
      const std::string why = a_.input + ": frame " + std::to_string(r.sequence) + " is " +
                              std::to_string(image.width) + "x" + std::to_string(image.height) + ", " + camera_size();
      std::cerr << "ccdlane replay: " << why << '\n';
      if (first_unread_.empty()) first_unread_ = why;
      usable = false;
    }
    // The vehicle as the daemon had it when it recorded the frame.
    replay_frame(usable ? &image : nullptr, recorded_frame_meta(r));
  }
  if (frames_ == 0 && log_->lost_events() == 0)
    throw UsageError(a_.input + ": no frames on channel " + log_->channel() + " (" +
                     std::to_string(log_->other_events()) + " events on other channels)");
}

void Replay::replay_video() {
  // A dashcam records no gyro, speed or indicator: [vehicle] speed_kmh, no indicator.
  video_problem_ = read_video_recording(*video_, [&](const ImageView& image, std::uint64_t index, std::int64_t t_ns) {
    FrameMeta meta;
    meta.sequence = index;
    meta.t_ns = t_ns;
    replay_frame(&image, meta);
  });
}

void Replay::check_observability(const FrameMeta& meta) {
  // As the daemon does at start: refuse solves that cannot determine what they are asked
  // for. The roll is measured when the recording's first readable frame carries a gyro
  // reading, or when it was made with a gyro (whose first readings may come after the
  // first frames), as the daemon counts a configured gyro.
  observability_checked_ = true;
  if (const Observability o = observability(options_, meta.gyro || gyro_configured_); o != Observability::observable)
    throw UsageError(a_.config + ": " + explain(o) + " (the frames of " + a_.input + " carry " +
                     (meta.gyro ? "" : "no ") + "gyro readings)");
}

// One frame through the pipeline; `image` null for a frame that could not be read.
void Replay::replay_frame(const ImageView* recorded, const FrameMeta& meta) {
  ImageView conditioned;
  if (recorded) conditioned = conditioner_.apply(*recorded, meta.sequence);
  const ImageView* image = recorded ? &conditioned : nullptr;
  if (image && !observability_checked_) check_observability(meta);
  // Nothing is live in a recording; the gyro is judged as ccdlaned judged it: a
  // configured one that gave the frame no reading failed.
  LiveReadings live;
  live.gyro_delivering = meta.gyro || !gyro_configured_;
  const FrameInputs in = frame_inputs(image, meta.sequence, meta, live, gyro_configured_);
  ++frames_;
  // A still is alone whether or not its picture could be read: an unreadable one carries
  // nothing of the still before it either (its state says searching, no line coasts).
  if (a_.stills) estimator_.reset();
  if (!image) {
    ++skipped_;
    print_json_line(*out_, lane_estimate_json(estimator_.estimate(in), a_.sigmas));
    check_written(*out_, out_name_);
    return;
  }
  const auto t0 = std::chrono::steady_clock::now();
  LaneEstimate e = estimator_.estimate(in);
  const double dt = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  e.latency_us = static_cast<std::int64_t>(dt * 1e6);
  total_s_ += dt;
  if (dt > worst_s_) worst_s_ = dt, worst_frame_ = meta.sequence;
  ok_ += e.ok;
  print_json_line(*out_, lane_estimate_json(e, a_.sigmas));
  check_written(*out_, out_name_);
  if (overlay_video_) overlay_video_->add(*image, e, estimator_, seen_);
  if (!a_.overlay.empty()) write_overlays(*image, meta.sequence);
}

void Replay::write_overlays(const ImageView& image, std::uint64_t index) {
  char name[32], paint[32];
  std::snprintf(name, sizeof name, "/%06llu.png", static_cast<unsigned long long>(index));
  std::snprintf(paint, sizeof paint, "/%06llu-paint.png", static_cast<unsigned long long>(index));
  try {
    draw_overlay(a_.overlay + name, image, estimator_, seen_);
    const auto [first, last] = searched_rows(image, estimator_, seen_);
    write_paint_measure_png(a_.overlay + paint, image, first, last);
  } catch (const std::runtime_error& failure) {
    // Each PNG is whole or absent (temporary name, then rename): say what is there.
    throw std::runtime_error(std::string(failure.what()) + "; " + std::to_string(overlays_) +
                             " complete overlays remain in " + a_.overlay + ", no partial file");
  }
  ++overlays_;
}

int Replay::finish() {
  const std::size_t processed = frames_ - (skipped_ - csv_issues_);
  // Nothing replayed is bad input, not a result: no output file is left.
  if (((frames_ > 0 && processed == 0) || (video_ && frames_ == 0)) && file_) file_.reset();
  if (file_)
    file_->commit();
  else
    flush_checked(std::cout, "standard output");
  if (overlay_video_ && overlay_video_->frames() > 0) {  // the frames before a damaged one are kept too
    overlay_video_->finish();
    std::cerr << "ccdlane replay: " << overlay_video_->frames() << " annotated frames in " << a_.overlay_video << '\n';
  }
  char summary[256];
  std::snprintf(summary, sizeof summary,
                "ccdlane replay: %zu frames, %zu ok, %zu skipped; per frame %.3f ms mean, %.3f ms worst (frame %llu)",
                frames_ + csv_issues_, ok_, skipped_, processed ? 1e3 * total_s_ / static_cast<double>(processed) : 0.0,
                1e3 * worst_s_, static_cast<unsigned long long>(worst_frame_));
  std::cerr << summary << '\n';
  // Frames lost to a damaged or cut log are a failed replay even when the rest went
  // well: the output is kept, the status says it is incomplete.
  if (log_ && log_->lost_events() > 0) {
    std::fprintf(stderr, "ccdlane replay: %s: %llu event(s) lost to damage (%llu bytes skipped)%s\n", a_.input.c_str(),
                 static_cast<unsigned long long>(log_->lost_events()),
                 static_cast<unsigned long long>(log_->lost_bytes()),
                 log_->truncated() ? ", the last one cut short" : "");
    return 1;
  }
  if (!video_problem_.empty()) throw UsageError(video_problem_);
  if (frames_ > 0 && processed == 0)
    throw UsageError(a_.input + ": none of the frames could be read" +
                     (first_unread_.empty() ? std::string() : " (the first: " + first_unread_ + ")"));
  return 0;
}

}  // namespace

CommandAction setup_replay(CLI::App& sub) {
  auto a = std::make_shared<ReplayArgs>();
  sub.add_option("config", a->config, "configuration file (TOML)")->required();
  sub.add_option("input", a->input,
                 "frame directory (frames.csv + PGM, PPM, PNG or JPEG frames), an LCM log of ccdlane.frame_t on <[lcm] "
                 "prefix>FRAMES (ccdlane record, or lcm-logger on a ccdlaned with [lcm] publish_frames), or a video "
                 "(MP4, MKV, MOV, AVI: H.264, H.265, MJPEG)")
      ->required();
  sub.add_option("--out", a->out, "write the JSON Lines here instead of stdout");
  sub.add_option("--overlay", a->overlay,
                 "write here, per frame, a PNG with the marks, picks and fitted lines (NNNNNN.png) and one of the "
                 "lane-paint measure detection scanned (NNNNNN-paint.png)");
  sub.add_option("--overlay-video", a->overlay_video,
                 "write an annotated video here (H.264; .mp4, .mkv, .mov): each frame at its own time with the lines "
                 "found, the own lane filled, the candidate marks faint, a strip with width, offset, heading, radius, "
                 "state and LDW availability, and a departure warning on its side while it is held");
  sub.add_option("--condition", a->condition,
                 "replay the pictures as another camera or light would give them: scale=TIMES (a camera of that "
                 "many times the pixels along each side, the same chip and lens; the lines and pose come out as "
                 "ever, scored against the recorded camera and labels), blur=PX (Gaussian sigma), "
                 "light=SHARE (every level times it), noise=LEVELS (Gaussian sigma, 8-bit levels, seeded by the "
                 "frame's number), shade=SHARE (a bridge's shadow across the rows from shade_top to shade_bottom, "
                 "shares of the height, by default 0.55 to 0.7), dapple=SHARE (trees' shadows over dapple_cover of "
                 "the road, by default 0.4, drifting down the picture frame by frame), jpeg=QUALITY (through a JPEG "
                 "encoder at that quality, 1-100, and back, last: a dashcam's or a dataset's compression), e.g. "
                 "blur=1,light=0.3,noise=3; "
                 "the overlays show them so");
  sub.add_flag("--sigmas", a->sigmas, "add the solver's standard deviations to each object (\"sigma\")");
  sub.add_flag("--stills", a->stills,
               "each frame on its own: no pose, line, mount or filter state carried from one frame to the next "
               "(benchmark pictures: stills of unrelated clips)");
  sub.footer(
      "Runs detect -> solve (gyro roll/pitch from frames.csv as priors) -> track -> lane metrics on every "
      "frame, printing one JSON object per frame (docs/interfaces.md); from an LCM log, the gyro reading and "
      "timestamp each frame_t carries, other channels ignored; from a video, no gyro and [vehicle] speed_kmh. A "
      "damaged or cut video, or one whose times go backwards, exits 2 after the frames before it are written. "
      "Damaged frames are reported once each "
      "on stderr, counted, and give {\"ok\": false, \"reason\": \"no_frame\"}; a summary goes to stderr.");
  return [a] { return Replay(*a).run(); };
}

}  // namespace ccdlane::cli
