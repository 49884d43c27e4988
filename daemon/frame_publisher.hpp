// [lcm] publish_frames: every processed frame also goes out as a ccdlane.frame_t on
// <prefix>FRAMES, so that lcm-logger records a drive `ccdlane replay` turns back into the
// same lane estimates. A FrameProcessor decorator, on the processing thread (the capture
// thread must never wait on the network), allocation-free after construction.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <ccdlane/frame_t.hpp>
#include <lcm/lcm-cpp.hpp>

#include "app/config.hpp"
#include "daemon/frame_processor.hpp"
#include "bus/lcm_publisher.hpp"
#include "drivers/frame_source.hpp"

namespace ccdlane {

class FramePublishingProcessor final : public FrameProcessor {
 public:
  // Sizes the message and its encode buffer for width x height frames of `format` now.
  // `bus` must outlive this.
  FramePublishingProcessor(std::unique_ptr<FrameProcessor> inner, lcm::LCM& bus, std::string channel, int width,
                           int height, PixelFormat format);

  // Runs the inner processor, then publishes the frame under the sequence number and
  // frame time the pipeline gives its lane message (meta.sequence, meta.frame_t_ns()) with
  // the gyro reading the processor was given (or none), so a replay of the log keys and
  // primes every frame exactly as here. Only processed frames go out, in processing order
  // (after any drop): the log holds the very frame stream the estimator's tracking saw. Adds the frame's send time (~0.3 ms at 800x600 on
  // loopback) to the lane message's latency.
  LaneEstimate process(const ImageView& image, const FrameMeta& meta, std::optional<Gx1Angles> attitude) override;

  std::uint64_t published() const { return published_.load(std::memory_order_relaxed); }
  std::uint64_t failed() const { return failed_.load(std::memory_order_relaxed); }  // encode or publish errors
  const std::string& channel() const { return channel_; }

 private:
  std::unique_ptr<FrameProcessor> inner_;
  lcm::LCM& bus_;
  std::string channel_;
  frame_t message_{};
  std::vector<std::uint8_t> bytes_;
  std::atomic<std::uint64_t> published_{0}, failed_{0};
};

// ccdlaned's hook: `processor` wrapped in a FramePublishingProcessor on the publisher's
// bus when [lcm] publish_frames is set, else `processor` itself. Call after source->open().
std::unique_ptr<FrameProcessor> with_frame_publishing(std::unique_ptr<FrameProcessor> processor, const Config& config,
                                                      LcmPublisher& publisher, const FrameSource& source);

}  // namespace ccdlane
