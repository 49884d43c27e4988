// Lane estimates and status onto the LCM bus of [lcm] url, without allocating per
// message: one reused message object and encode buffers sized at construction.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <ccdlane/frame_t.hpp>
#include <ccdlane/lane_estimate_t.hpp>
#include <ccdlane/status_t.hpp>
#include <lcm/lcm-cpp.hpp>

#include "base/image_view.hpp"
#include "bus/frame_message.hpp"
#include "bus/lane_sink.hpp"

namespace ccdlane {

// The [lcm] table: which bus, and the prefix of every channel name.
struct LcmConfig {
  std::string url = "udpm://239.255.76.67:7667?ttl=0";
  std::string prefix = "CCDLANE_";
  bool publish_frames = false;  // raw frames on <prefix>FRAMES too, for lcm-logger (large: ~0.5 MB each)
  // The sender's name in every message (status_t.instance, lane_estimate_t.instance);
  // "" = "host:pid", which tells apart any two daemons but changes at every restart.
  std::string instance;

  bool operator==(const LcmConfig&) const = default;
};

// Longest text in a status_t string field; longer texts are cut to this by their writer.
constexpr std::size_t kStatusTextMax = 200;

class LcmPublisher : public LaneSink {
 public:
  // Opens the bus. Throws std::runtime_error naming the URL when LCM cannot.
  explicit LcmPublisher(const LcmConfig& config);

  // lcm::LCM::publish(channel, const T*) encodes into a `new` buffer on every call; this
  // encodes into the preallocated one and publishes the bytes.
  bool publish_lane(const LaneEstimate& estimate, std::int64_t capture_utime, std::int64_t publish_utime) override;
  // Strings longer than kStatusTextMax are refused (false), never reallocated.
  bool publish_status(const status_t& status);

  // [lcm] publish_frames: sizes the frame message and its encode buffer for width x height
  // frames of `format` now (the one allocation); from then on publish_frame() sends each
  // frame on <prefix>FRAMES (~0.3 ms at 800x600 on loopback).
  void enable_frames(int width, int height, PixelFormat format);
  bool publishes_frames() const override { return !frame_bytes_.empty(); }
  // False (and nothing sent) for a frame of another size or format than enabled, or when
  // encoding or sending fails.
  bool publish_frame(const ImageView& image, const FrameRecord& record) override;
  const std::string& frames_channel() const { return frames_channel_; }

  const std::string& lanes_channel() const { return lanes_channel_; }
  const std::string& status_channel() const { return status_channel_; }
  const std::string& url() const { return url_; }

  // This daemon's name on the bus ("host:pid"), sent in every lane message (status
  // messages carry it from their writer). At most kStatusTextMax characters.
  void set_instance(const std::string& instance);
  const std::string& instance() const { return instance_; }
  // Listens on the status channel for status messages of other instances. Allocates the
  // receive message once; handling the bus then allocates nothing for status-sized texts.
  void watch_for_other_instances();
  // The instance of another publisher seen on the status channel, the first time one is
  // seen (once); else null. Any thread: the bus may be handled on another (ccdlaned's
  // bus thread, which calls lcm_handle on bus() for every subscriber).
  const char* take_other_instance();
  // For a single-threaded owner: handles what arrived, without waiting, then
  // take_other_instance(). Never while another thread handles bus().
  const char* poll_bus();
  lcm::LCM& bus() { return *lcm_; }

 private:
  bool publish_bytes(const std::string& channel, std::uint8_t* buffer, int capacity, const auto& message);

  static void on_status(const lcm_recv_buf_t* rbuf, const char* channel, void* self);

  std::string url_;
  std::string instance_;
  status_t received_{};                         // the last status seen on the bus, decoded in place
  bool watching_ = false, other_seen_ = false;  // the handling thread's
  // Written once by the handling thread before other_new_ is released.
  char other_instance_[kStatusTextMax + 1] = {};
  std::atomic<bool> other_new_{false};
  std::unique_ptr<lcm::LCM> lcm_;
  std::string lanes_channel_, status_channel_, frames_channel_;
  lane_estimate_t lane_message_{};
  std::unique_ptr<std::uint8_t[]> lane_bytes_, status_bytes_;
  int lane_capacity_ = 0, status_capacity_ = 0;
  frame_t frame_message_{};
  std::vector<std::uint8_t> frame_bytes_;
};

}  // namespace ccdlane
