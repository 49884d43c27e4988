// The interface every frame source implements (V4L2, Aravis, frame directory, synthetic
// road): capture one frame into a caller-owned buffer of the fixed pool.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <optional>
#include <string>

#include "base/gx1_angles.hpp"
#include "base/image_view.hpp"
#include "base/turn_indicator.hpp"

namespace ccdlane {

enum class CaptureStatus : std::uint8_t {
  frame,          // `into` holds a new frame, `meta` describes it
  timeout,        // nothing arrived within the timeout (the stream may be stalled)
  recovering,     // the device is gone or restarting; capture() keeps trying with backoff
  end_of_stream,  // a finite source (frame directory without loop) has no more frames
  error,          // this frame was bad (counted); the next call may succeed
};

struct FrameMeta {
  std::uint64_t sequence = 0;     // the source's own frame counter (gaps = dropped frames)
  std::int64_t t_ns = 0;          // CLOCK_MONOTONIC, from the driver where it gives one
  std::optional<Gx1Angles> gyro;  // a recorded gyro reading (frame directories, synth)
  // The frame's own timestamp when the source plays a recording (frame directory, the
  // synthetic drive): its t_ns as recorded, which estimates and re-recorded frames carry,
  // so that a frame keeps its identity however fast it is played. t_ns stays the capture
  // time on this machine's clock, which a live gyro and the latencies are measured on.
  std::optional<std::int64_t> recorded_t_ns;
  // The vehicle at the frame as recorded (frames.csv's speed_kmh and turn_indicator
  // columns), so that a recording plays with the inputs it was made with; empty when the
  // recording has no such value (live sources: the daemon takes the bus's vehicle state).
  std::optional<double> speed_kmh;
  std::optional<double> yaw_rate_radps;  // + turning left (a logged frame_t's)
  std::optional<TurnIndicator> indicator;

  // The timestamp a frame goes out under (lane estimates, frame_t): as recorded, else t_ns.
  std::int64_t frame_t_ns() const { return recorded_t_ns.value_or(t_ns); }
};

struct SourceCounters {
  std::uint64_t frames = 0;   // delivered
  std::uint64_t dropped = 0;  // sequence gaps seen from the device
  std::uint64_t errors = 0;   // bad frames, buffer status errors, damaged files
  std::uint64_t timeouts = 0;
  std::uint64_t reconnects = 0;  // successful reopen/restart after a loss or stall
};

class FrameSource {
 public:
  virtual ~FrameSource() = default;

  // Opens, configures and starts streaming. Returns "" on success, else one line saying
  // what is wrong (device, cause). May allocate; called before the daemon is ready.
  virtual std::string open() = 0;

  // Size and format of the frames capture() writes; valid after a successful open().
  virtual int width() const = 0;
  virtual int height() const = 0;
  virtual PixelFormat format() const = 0;

  // Waits up to timeout_ms for the next frame and copies (or converts, e.g. YUYV -> Y)
  // it into `into`, which has width() x height() pixels of format(). Never allocates,
  // never throws. Recovery from a lost device happens inside, with backoff.
  virtual CaptureStatus capture(const MutableImageView& into, FrameMeta& meta, int timeout_ms) = 0;

  // Stops streaming and releases the device.
  virtual void close() = 0;

  // What the source is, for logs and status: "v4l2:/dev/video0 800x600 GREY 30 fps".
  virtual std::string describe() const = 0;
  // The last problem, for status lines ("" when none): e.g. "device lost: ENODEV".
  virtual std::string last_problem() const = 0;
  // The same, copied NUL-terminated into `out` (cut to fit) for the capture thread, which
  // must not allocate once the daemon is ready: sources that keep the text in a fixed
  // buffer override this; the default goes through last_problem().
  virtual void copy_last_problem(char* out, std::size_t size) const {
    if (size > 0) std::snprintf(out, size, "%s", last_problem().c_str());
  }
  virtual SourceCounters counters() const = 0;
};

}  // namespace ccdlane
