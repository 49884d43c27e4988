// `ccdlane grab SOURCE`: grabs frames from a camera through the same FrameSource and frame
// pool the daemon uses, reports what the device is and how it performed (frames, drops,
// measured rate, capture-to-delivery latency), and optionally records a frame directory.
#include <algorithm>
#include <cstdio>
#include <iostream>
#include <memory>
#include <optional>
#include <stdexcept>
#include <vector>

#include "drivers/camera/camera_factory.hpp"
#include "drivers/camera/frame_pool.hpp"
#include "drivers/device_state.hpp"
#include "drivers/frames/frame_directory_writer.hpp"
#include "tools/ccdlane/command.hpp"

namespace ccdlane::cli {
namespace {

struct GrabArgs {
  std::string source;
  int count = 100;
  std::string out;
  int width = 800;
  int height = 600;
  double fps = 30;
  std::string format = "mono8";
  int buffers = 8;
  std::optional<double> exposure_us;
  std::optional<double> gain;
  int no_frame_timeout_s = 5;
};

double percentile_ms(std::vector<std::int64_t>& sorted_ns, double p) {
  if (sorted_ns.empty()) return 0;
  const auto i = static_cast<std::size_t>(p * static_cast<double>(sorted_ns.size() - 1) + 0.5);
  return static_cast<double>(sorted_ns[i]) * 1e-6;
}

int grab(const GrabArgs& a) {
  CameraSettings s;
  s.width = a.width;
  s.height = a.height;
  s.fps = a.fps;
  s.format = a.format == "mono16" ? PixelFormat::mono16 : PixelFormat::mono8;
  s.buffer_count = a.buffers;
  s.exposure_us = a.exposure_us;
  s.gain = a.gain;
  std::unique_ptr<FrameSource> camera;
  try {
    camera = make_camera(a.source, s);
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());
  }
  if (const std::string error = camera->open(); !error.empty()) throw std::runtime_error(error);

  std::optional<FrameDirectoryWriter> writer;
  if (!a.out.empty()) writer.emplace(a.out, FrameDirectoryLayout{});
  FramePool pool({.count = 2, .width = camera->width(), .height = camera->height(), .format = camera->format()});
  std::vector<std::int64_t> latency_ns;
  latency_ns.reserve(static_cast<std::size_t>(a.count));
  std::int64_t first_t = 0, last_t = 0, last_frame_wall = monotonic_ns();
  int received = 0;
  while (received < a.count) {
    const int i = pool.borrow();
    FrameMeta& meta = pool.meta(i);
    const CaptureStatus st = camera->capture(pool.view(i), meta, 500);
    const std::int64_t delivered = monotonic_ns();
    if (st == CaptureStatus::frame) {
      latency_ns.push_back(delivered - meta.t_ns);
      (received == 0 ? first_t : last_t) = meta.t_ns;
      ++received;
      last_frame_wall = delivered;
      if (writer) writer->write(pool.view(i), meta.t_ns);
    } else if (delivered - last_frame_wall > std::int64_t{a.no_frame_timeout_s} * 1'000'000'000) {
      (void)pool.give_back(i);
      throw std::runtime_error(camera->describe() + ": no frame for " + std::to_string(a.no_frame_timeout_s) +
                               " s after " + std::to_string(received) +
                               " frames; last problem: " + camera->last_problem());
    }
    (void)pool.give_back(i);
  }
  if (writer) writer->finish();
  const SourceCounters c = camera->counters();
  camera->close();

  std::sort(latency_ns.begin(), latency_ns.end());
  const double span_s = static_cast<double>(last_t - first_t) * 1e-9;
  std::printf("device: %s\n", camera->describe().c_str());
  std::printf("format: %dx%d %s\n", camera->width(), camera->height(),
              camera->format() == PixelFormat::mono16 ? "mono16" : "mono8");
  std::printf("frames: %d received, %llu dropped, %llu errors, %llu timeouts, %llu reconnects\n", received,
              static_cast<unsigned long long>(c.dropped), static_cast<unsigned long long>(c.errors),
              static_cast<unsigned long long>(c.timeouts), static_cast<unsigned long long>(c.reconnects));
  if (received > 1 && span_s > 0)
    std::printf("rate: %.2f fps measured over %.3f s (frame timestamps)\n", (received - 1) / span_s, span_s);
  std::printf("latency (frame timestamp to delivery): p50 %.3f ms, p99 %.3f ms, max %.3f ms\n",
              percentile_ms(latency_ns, 0.5), percentile_ms(latency_ns, 0.99), percentile_ms(latency_ns, 1.0));
  if (writer) std::printf("out: %s (%zu frames)\n", writer->path().c_str(), writer->frames_written());
  return 0;
}

}  // namespace

CommandAction setup_grab(CLI::App& sub) {
  auto a = std::make_shared<GrabArgs>();
  sub.add_option("source", a->source, "v4l2:/dev/videoN or aravis:ID (IP address, camera id/serial, Fake_1)")
      ->required();
  sub.add_option("--count", a->count, "frames to grab (default 100)")->check(CLI::Range(1, 10'000'000));
  sub.add_option("--out", a->out, "record a frame directory (PGM + frames.csv) there");
  sub.add_option("--width", a->width, "frame width in pixels (default 800)")->check(CLI::Range(1, 16384));
  sub.add_option("--height", a->height, "frame height in pixels (default 600)")->check(CLI::Range(1, 16384));
  sub.add_option("--fps", a->fps, "frame rate; 0 leaves the device's (default 30)")->check(CLI::Range(0.0, 10000.0));
  sub.add_option("--format", a->format, "mono8 or mono16 (default mono8)")->check(CLI::IsMember({"mono8", "mono16"}));
  sub.add_option("--buffers", a->buffers, "driver buffers (default 8)")->check(CLI::Range(2, 32));
  sub.add_option("--exposure-us", a->exposure_us, "exposure time, microseconds")->check(positive_number());
  sub.add_option("--gain", a->gain, "gain, in the device's units");
  sub.footer(
      "Prints the device, the format obtained, frames received and dropped, the measured rate and the "
      "latency from each frame's timestamp (CLOCK_MONOTONIC) to its delivery. Exit 1 when the camera "
      "cannot be opened or stops delivering.");
  return [a] { return grab(*a); };
}

}  // namespace ccdlane::cli
