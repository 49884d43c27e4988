// Raw frames onto the bus from the processing thread, into buffers sized at start-up.
#include "daemon/frame_publisher.hpp"

#include "bus/channels.hpp"
#include "base/clock.hpp"
#include "bus/frame_message.hpp"

namespace ccdlane {

FramePublishingProcessor::FramePublishingProcessor(std::unique_ptr<FrameProcessor> inner, lcm::LCM& bus,
                                                   std::string channel, int width, int height, PixelFormat format)
    : inner_(std::move(inner)), bus_(bus), channel_(std::move(channel)) {
  prepare_frame_message(message_, width, height, format);
  bytes_.resize(static_cast<std::size_t>(message_.getEncodedSize()));
}

LaneEstimate FramePublishingProcessor::process(const ImageView& image, const FrameMeta& meta,
                                               std::optional<Gx1Angles> attitude) {
  const LaneEstimate estimate = inner_->process(image, meta, attitude);
  // Wall-clock time of the capture: meta.t_ns is CLOCK_MONOTONIC.
  const std::int64_t utime = realtime_us() - (monotonic_ns() - meta.t_ns) / 1000;
  // Keyed as the pipeline keys the lane message: the source's sequence and frame time.
  const FrameRecord record{meta.sequence, meta.frame_t_ns(), utime, attitude};
  int size = -1;
  if (to_frame_message(image, record, message_))
    size = message_.encode(bytes_.data(), 0, static_cast<int>(bytes_.size()));
  if (size >= 0 && bus_.publish(channel_, bytes_.data(), static_cast<unsigned int>(size)) == 0)
    published_.fetch_add(1, std::memory_order_relaxed);
  else
    failed_.fetch_add(1, std::memory_order_relaxed);
  return estimate;
}

std::unique_ptr<FrameProcessor> with_frame_publishing(std::unique_ptr<FrameProcessor> processor, const Config& config,
                                                      LcmPublisher& publisher, const FrameSource& source) {
  if (!config.lcm.publish_frames) return processor;
  return std::make_unique<FramePublishingProcessor>(std::move(processor), publisher.bus(),
                                                    channel_name(config.lcm.prefix, Channel::frames), source.width(),
                                                    source.height(), source.format());
}

}  // namespace ccdlane
