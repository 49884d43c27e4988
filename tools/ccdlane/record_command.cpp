// `ccdlane record SOURCE --out DIR|FILE.lcmlog`: records frames from a camera (the same
// drivers as ccdlaned), the synthetic road, or a frame directory into a frame directory
// or an LCM log of ccdlane.frame_t messages, with the gyro reading at each frame when
// there is one. Either output replays with `ccdlane replay`, to the same estimates.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <optional>
#include <thread>
#include <vector>

#include <lcm/lcm-cpp.hpp>

#include "app/config_loader.hpp"
#include "app/gx1_attitude_provider.hpp"
#include "app/gyro_factory.hpp"
#include "base/clock.hpp"
#include "base/image_buffer.hpp"
#include "bus/channels.hpp"
#include "bus/frame_log.hpp"
#include "bus/vehicle_state_listener.hpp"
#include "core/synth/road_renderer.hpp"
#include "core/synth/synth_drive.hpp"
#include "drivers/camera/camera_factory.hpp"
#include "drivers/camera/frame_pool.hpp"
#include "drivers/device_state.hpp"
#include "drivers/frames/frame_directory.hpp"
#include "drivers/frames/frame_directory_writer.hpp"
#include "tools/ccdlane/command.hpp"
#include "tools/ccdlane/video_recording.hpp"

namespace ccdlane::cli {
namespace {

struct RecordArgs {
  std::string source;
  std::string out;
  std::string config;
  std::optional<double> seconds;
  std::optional<int> count;
  double fps = 30.0;
  bool vehicle_state = false;       // --vehicle-state
  std::optional<double> speed_kmh;  // --speed-kmh: a constant speed for a video (a dashcam has no CAN)
};

// `--vehicle-state`: the CAN gateway's vehicle_state_t on the [lcm] bus, taken between
// frames on the recording thread (the only one handling this bus), so that a recording
// of a live camera carries each frame's speed, yaw rate and indicator as ccdlaned would
// have used them.
class VehicleBus {
 public:
  explicit VehicleBus(const Config& config) : lcm_(config.lcm.url) {
    if (!lcm_.good())
      throw std::runtime_error("record: --vehicle-state: cannot open the bus \"" + config.lcm.url + "\"");
    listener_ = std::make_unique<VehicleStateListener>(lcm_.getUnderlyingLCM(),
                                                       channel_name(config.lcm.prefix, Channel::vehicle));
  }
  // The state at now: what arrived is taken first; stale or none gives no values.
  void fill(FrameRecord& record) {
    while (lcm_.handleTimeout(0) > 0) {
    }
    const VehicleInputs in = vehicle_inputs(listener_->latest(), monotonic_ns(), kVehicleStateMaxAgeNs);
    if (in.speed_mps) record.speed_kmh = *in.speed_mps * 3.6;
    record.yaw_rate_radps = in.yaw_rate_radps;
    record.indicator = in.indicator;
  }

 private:
  lcm::LCM lcm_;
  std::unique_ptr<VehicleStateListener> listener_;
};

bool is_log_path(const std::string& out) {
  constexpr std::string_view kSuffix = ".lcmlog";
  return out.size() > kSuffix.size() && out.compare(out.size() - kSuffix.size(), kSuffix.size(), kSuffix) == 0;
}

// The live 3DM-GX1 of [gyro] device (or the emulator for "emulated"): the daemon's
// Gx1AttitudeProvider, read by its own thread; frames take the reading interpolated at
// their time. Once it streams, its problems (not the emulator's chatter) go to stderr;
// a failed open is the one line of the error it throws.
class LiveGyro {
 public:
  explicit LiveGyro(const Config& config) {
    const LogSink log = [this](LogLevel level, const char* category, const char* line) {
      if (level != LogLevel::info && streaming_.load())
        std::cerr << "ccdlane record: " << category << ": " << line << '\n';
    };
    provider_ = make_attitude_provider(config, log);
    if (const std::string why = provider_->open(); !why.empty()) throw std::runtime_error(why);
    streaming_.store(true);
    thread_ = std::thread([this] { provider_->run(stop_); });
    // Frames are recorded once the gyro streams, so that every frame has a reading.
    const std::int64_t give_up = monotonic_ns() + 2'000'000'000;
    while (!provider_->newest_sample_ns()) {
      if (monotonic_ns() > give_up) {
        stop_thread();
        throw std::runtime_error("gyro: " + config.gyro.device + ": no sample within 2 s of opening it");
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
  }
  ~LiveGyro() { stop_thread(); }
  LiveGyro(const LiveGyro&) = delete;
  LiveGyro& operator=(const LiveGyro&) = delete;

  // Waits for a sample after t_ns (up to the history's age limit), so that the reading is
  // interpolated between two samples rather than the last one held. Recording is not
  // real time: the camera's driver buffers hold the frames meanwhile.
  std::optional<Gx1Angles> at(std::int64_t t_ns) {
    for (const std::int64_t give_up = monotonic_ns() + options_.max_age_ns; monotonic_ns() < give_up;
         std::this_thread::sleep_for(std::chrono::milliseconds(1)))
      if (const auto newest = provider_->newest_sample_ns(); newest && *newest >= t_ns) break;
    const std::optional<Gx1Angles> angles = provider_->attitude_at(t_ns);
    missing_ += !angles;
    return angles;
  }
  std::uint64_t missing() const { return missing_; }

 private:
  void stop_thread() {
    stop_.store(true);
    if (thread_.joinable()) thread_.join();
    provider_->close();
  }

  const gx1::SessionOptions options_{};  // the provider's own: how old a sample may be
  std::unique_ptr<AttitudeProvider> provider_;
  std::atomic<bool> stop_{false}, streaming_{false};
  std::thread thread_;
  std::uint64_t missing_ = 0;
};

// Where frames go, and when to stop: --count frames, --seconds of frame time, or a signal.
class Recording {
 public:
  // `vehicle`: the frames come with vehicle values (speed, indicator) to keep.
  Recording(const RecordArgs& a, const Config& config, bool gyro, std::optional<int> default_count,
            bool vehicle = false)
      : count_(a.count     ? a.count
               : a.seconds ? std::nullopt
                           : default_count),
        seconds_(a.seconds) {
    try {
      if (is_log_path(a.out))
        log_.emplace(a.out, channel_name(config.lcm.prefix, Channel::frames));
      else
        directory_.emplace(a.out, FrameDirectoryLayout{gyro, {}, vehicle});
    } catch (const std::runtime_error& e) {  // FrameLogError, FrameDirectoryError
      throw UsageError(e.what());
    }
  }

  // False once the recording has all it wants; `t_ns` is the next frame's time.
  bool wants(std::int64_t t_ns) const {
    if (stop_requested()) return false;  // SIGINT/SIGTERM: keep the frames so far, finish the files
    if (count_ && written_ >= static_cast<std::size_t>(*count_)) return false;
    if (seconds_ && written_ > 0 && static_cast<double>(t_ns - first_t_ns_) * 1e-9 >= *seconds_) return false;
    return true;
  }
  bool wants_more() const { return wants(last_t_ns_); }

  void write(const ImageView& image, const FrameRecord& record) {
    if (written_ == 0) first_t_ns_ = record.t_ns;
    last_t_ns_ = record.t_ns;
    try {
      if (log_)
        log_->write(image, record);
      else
        directory_->write(image, record.t_ns, record.gyro, {}, FrameVehicle{record.speed_kmh, record.indicator});
    } catch (const std::runtime_error& failure) {  // FrameLogError, FrameDirectoryError: a full disk
      keep_written(failure.what());
    }
    ++written_;
    with_gyro_ += record.gyro.has_value();
    width_ = image.width, height_ = image.height, format_ = image.format;
  }

  void finish(const std::string& from) {
    if (written_ == 0) throw std::runtime_error("record: no frame was recorded from " + from);
    try {
      if (log_)
        log_->finish();
      else
        directory_->finish();
    } catch (const std::runtime_error& failure) {
      keep_written(failure.what());
    }
    const double span = static_cast<double>(last_t_ns_ - first_t_ns_) * 1e-9;
    std::fprintf(stderr, "ccdlane record: %zu frames of %dx%d %s (%.3f s) from %s, %zu with a gyro reading, to %s\n",
                 written_, width_, height_,
                 format_ == PixelFormat::mono16 ? "mono16"
                 : is_colour(format_)           ? "colour"
                                                : "mono8",
                 span, from.c_str(), with_gyro_, log_ ? log_->path().c_str() : directory_->path().c_str());
  }

  // A recording that cannot go on keeps the frames it has: a long drive must not lose
  // everything to a full disk. Says how many were saved, then fails the command.
  [[noreturn]] void keep_written(const std::string& failure) {
    const std::size_t kept = log_ ? log_->frames_written() : directory_->frames_kept();
    const std::string why = log_ ? log_->keep_written() : directory_->keep_written();
    const std::string path = log_ ? log_->path() : directory_->path();
    if (!why.empty())
      throw std::runtime_error(failure + "; the " + std::to_string(kept) +
                               " frames before it could not be kept: " + why);
    throw std::runtime_error(failure + "; recording stopped: the " + std::to_string(kept) +
                             " frames before it are saved in " + path);
  }

  // Wall-clock capture time for frame-time t_ns: the first frame at `start`, the rest
  // following their own timestamps (so lcm-logplayer plays a log at its recorded pace).
  std::int64_t utime_of(std::int64_t t_ns, std::int64_t start_utime) const {
    return start_utime + (written_ == 0 ? 0 : (t_ns - first_t_ns_) / 1000);
  }

 private:
  std::optional<int> count_;
  std::optional<double> seconds_;
  std::optional<FrameLogWriter> log_;
  std::optional<FrameDirectoryWriter> directory_;
  std::size_t written_ = 0, with_gyro_ = 0;
  std::int64_t first_t_ns_ = 0, last_t_ns_ = 0;
  int width_ = 0, height_ = 0;
  PixelFormat format_ = PixelFormat::mono8;
};

void record_synth(const RecordArgs& a, const Config& config) {
  const SynthConfig& s = config.synth;
  const SynthDrive drive(config.synth, config.nominal_pose());
  RoadRenderer renderer(config.camera, s);
  const ImageBuffer buffer(config.camera.Nu, config.camera.Nv, renderer.format(), s.bits);
  const MutableImageView& image = buffer.view();
  Recording out(a, config, s.gyro, s.frames);
  const std::int64_t start = realtime_us();
  for (std::uint64_t k = 0;; ++k) {
    const SynthFrame f = drive.frame(k);
    if (!out.wants(f.t_ns)) break;
    renderer.render(f, image);
    out.write(image,
              {k, f.t_ns, out.utime_of(f.t_ns, start), s.gyro ? std::optional<Gx1Angles>(f.gyro) : std::nullopt});
  }
  out.finish("synth");
}

void record_frames(const RecordArgs& a, const Config& config, const std::string& path) {
  std::optional<FrameDirectory> dir;
  try {
    dir.emplace(path);
  } catch (const FrameDirectoryError& e) {
    throw UsageError(e.what());
  }
  for (const std::string& issue : dir->issues()) std::cerr << "ccdlane record: " << issue << '\n';
  if (!dir->note().empty()) std::cerr << "ccdlane record: " << dir->note() << '\n';
  const auto header = dir->probe_first();
  if (!header) throw UsageError(path + ": no frame of the directory can be read");
  const ImageBuffer buffer(header->width, header->height, header->format(),
                           header->format() == PixelFormat::mono16 ? header->significant_bits() : 8);
  const MutableImageView& image = buffer.view();
  Recording out(a, config, dir->has_gyro_columns(), static_cast<int>(dir->size()), dir->has_vehicle_columns());
  const std::int64_t start = realtime_us();
  for (std::size_t i = 0; i < dir->size(); ++i) {
    const FrameRow& row = dir->row(i);
    if (!out.wants(row.t_ns)) break;
    if (dir->read(i, image) != PgmFault::none) {
      std::cerr << "ccdlane record: " << dir->error() << " (skipped)\n";
      continue;
    }
    FrameRecord record{row.index, row.t_ns, out.utime_of(row.t_ns, start), row.gyro};
    record.speed_kmh = row.speed_kmh;  // the vehicle as recorded, so the copy replays alike
    record.indicator = row.indicator;
    out.write(image, record);
  }
  out.finish("frames:" + path);
}

// A video file: its frames at their container times, with no gyro, and the constant
// --speed-kmh when given (no indicator), so that the log replays as the drive was driven.
void record_video(const RecordArgs& a, const Config& config, const std::string& path) {
  // With --config the frames must be its camera's; without, the video's size is taken.
  Config sized = config;
  if (a.config.empty()) {
    try {
      const VideoReader probe(path);
      sized.camera.Nu = probe.width(), sized.camera.Nv = probe.height();
    } catch (const VideoError& e) {
      throw UsageError(e.what());
    }
  }
  const std::unique_ptr<VideoReader> video = open_video_recording(path, sized, a.config);
  Recording out(a, config, false, std::nullopt, a.speed_kmh.has_value());
  const std::int64_t start = realtime_us();
  bool stopped = false;
  const std::string problem =
      read_video_recording(*video, [&](const ImageView& image, std::uint64_t index, std::int64_t t_ns) {
        if (stopped || (stopped = !out.wants(t_ns))) return;
        FrameRecord record{index, t_ns, out.utime_of(t_ns, start), std::nullopt};
        record.speed_kmh = a.speed_kmh;
        out.write(image, record);
      });
  out.finish("video:" + path);
  if (!problem.empty()) throw UsageError(problem);
}

void record_camera(const RecordArgs& a, const Config& config) {
  CameraSettings settings;
  settings.width = config.camera.Nu;
  settings.height = config.camera.Nv;
  settings.fps = a.fps;
  std::unique_ptr<FrameSource> camera;
  try {
    camera = make_camera(a.source, settings);
  } catch (const std::invalid_argument& e) {
    throw UsageError(std::string("record: ") + e.what());
  }
  // The gyro first: the camera's first frames then already have readings around them.
  std::unique_ptr<LiveGyro> gyro;
  if (!config.gyro.device.empty()) gyro = std::make_unique<LiveGyro>(config);
  if (const std::string error = camera->open(); !error.empty()) throw std::runtime_error(error);
  try {
    FramePool pool({.count = 1, .width = camera->width(), .height = camera->height(), .format = camera->format()});
    std::unique_ptr<VehicleBus> vehicle;
    if (a.vehicle_state) vehicle = std::make_unique<VehicleBus>(config);
    Recording out(a, config, gyro != nullptr, std::nullopt, vehicle != nullptr);
    const int i = pool.borrow();
    const std::int64_t wall_start = monotonic_ns();
    while (out.wants_more()) {
      if (a.seconds && static_cast<double>(monotonic_ns() - wall_start) * 1e-9 > *a.seconds + 1.0) break;  // stalled
      FrameMeta& meta = pool.meta(i);
      if (camera->capture(pool.view(i), meta, 200) != CaptureStatus::frame) continue;
      if (!out.wants(meta.t_ns)) break;
      const std::int64_t utime = realtime_us_of_monotonic(meta.t_ns);
      FrameRecord record{meta.sequence, meta.t_ns, utime, gyro ? gyro->at(meta.t_ns) : std::nullopt};
      if (vehicle) vehicle->fill(record);
      out.write(pool.view(i), record);
    }
    out.finish(camera->describe());
    const SourceCounters c = camera->counters();
    if (c.dropped || c.errors)
      std::fprintf(stderr, "ccdlane record: the camera dropped %llu frames and reported %llu errors\n",
                   static_cast<unsigned long long>(c.dropped), static_cast<unsigned long long>(c.errors));
    if (gyro && gyro->missing())
      std::fprintf(stderr, "ccdlane record: %llu frames without a gyro reading (none close enough in time)\n",
                   static_cast<unsigned long long>(gyro->missing()));
  } catch (...) {
    camera->close();
    throw;
  }
  camera->close();
}

}  // namespace

CommandAction setup_record(CLI::App& sub) {
  auto a = std::make_shared<RecordArgs>();
  sub.add_option("source", a->source,
                 "v4l2:/dev/videoN, aravis:ID (IP address, camera id or serial, Fake_1), synth (the [synth] road "
                 "of --config), frames:DIR (a frame directory) or video:FILE (.mp4, .mkv, .mov, .avi)")
      ->required();
  sub.add_option("--out", a->out, "a frame directory to create, or FILE.lcmlog (an LCM log of ccdlane.frame_t)")
      ->required();
  sub.add_option("--config", a->config, "configuration (TOML): [camera] Nu x Nv, [gyro] device, [synth], [lcm] prefix");
  sub.add_option("--seconds", a->seconds, "stop after S seconds of frames")->check(positive_number());
  sub.add_option("--count", a->count, "stop after N frames")->check(CLI::Range(1, 100'000'000));
  sub.add_option("--fps", a->fps, "camera frame rate; 0 leaves the device's (default 30)")
      ->check(CLI::Range(0.0, 10000.0));
  sub.add_option("--speed-kmh", a->speed_kmh,
                 "video: the vehicle's speed at every frame (a dashcam records none); without it replay takes "
                 "[vehicle] speed_kmh")
      ->check(CLI::Range(0.0, 300.0));
  sub.add_flag("--vehicle-state", a->vehicle_state,
               "cameras: record each frame's speed, yaw rate and turn indicator from ccdlane.vehicle_state_t on the "
               "[lcm] bus (<[lcm] prefix>VEHICLE, as a CAN gateway publishes it for ccdlaned)");
  sub.footer(
      "Cameras record until --count, --seconds or Ctrl-C (SIGINT/SIGTERM finish the files cleanly), at "
      "[camera] Nu x Nv, with the [gyro] device's reading interpolated at each frame's time. synth records "
      "[synth] frames (or --count/--seconds of them), frames:DIR the whole directory. A log holds one "
      "ccdlane.frame_t event per frame on channel <[lcm] prefix>FRAMES; a frame directory holds PGM files "
      "and frames.csv (roll_deg,pitch_deg,yaw_deg when there is a gyro). Nothing is left behind on failure.");
  return [a] {
    const Config config = a->config.empty() ? default_config() : load_config_file(a->config);
    catch_stop_signals();
    if (a->source == "synth")
      record_synth(*a, config);
    else if (a->source.rfind("frames:", 0) == 0)
      record_frames(*a, config, a->source.substr(7));
    else if (a->source.rfind("video:", 0) == 0)
      record_video(*a, config, a->source.substr(6));
    else
      record_camera(*a, config);
    return 0;
  };
}

}  // namespace ccdlane::cli
