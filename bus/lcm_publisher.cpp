// The encode buffers are sized from the largest message each type can be: lane messages
// have a fixed size; status messages are bounded by kStatusTextMax per string.
#include "bus/lcm_publisher.hpp"

#include <cstdio>
#include <stdexcept>

#include "bus/channels.hpp"
#include "bus/lane_message.hpp"

namespace ccdlane {

LcmPublisher::LcmPublisher(const LcmConfig& config)
    : url_(config.url),
      lcm_(std::make_unique<lcm::LCM>(config.url)),
      lanes_channel_(channel_name(config.prefix, Channel::lanes)),
      status_channel_(channel_name(config.prefix, Channel::status)),
      frames_channel_(channel_name(config.prefix, Channel::frames)) {
  if (!lcm_->good()) throw std::runtime_error("lcm: cannot open the bus \"" + config.url + "\" ([lcm] url)");
  lane_capacity_ = lane_message_.getEncodedSize();
  status_t largest;
  largest.instance.assign(kStatusTextMax, 'x');
  largest.camera.assign(kStatusTextMax, 'x');
  largest.camera_problem.assign(kStatusTextMax, 'x');
  largest.gyro_problem.assign(kStatusTextMax, 'x');
  status_capacity_ = largest.getEncodedSize();
  lane_message_.instance.assign(kStatusTextMax, 'x');  // sized for the longest instance name
  lane_capacity_ = lane_message_.getEncodedSize();
  lane_message_.instance.clear();
  lane_bytes_ = std::make_unique<std::uint8_t[]>(static_cast<std::size_t>(lane_capacity_));
  status_bytes_ = std::make_unique<std::uint8_t[]>(static_cast<std::size_t>(status_capacity_));
}

bool LcmPublisher::publish_bytes(const std::string& channel, std::uint8_t* buffer, int capacity, const auto& message) {
  const int size = message.encode(buffer, 0, capacity);
  if (size < 0) return false;
  return lcm_->publish(channel, buffer, static_cast<unsigned int>(size)) == 0;
}

bool LcmPublisher::publish_lane(const LaneEstimate& estimate, std::int64_t capture_utime, std::int64_t publish_utime) {
  to_message(estimate, capture_utime, publish_utime, lane_message_);
  return publish_bytes(lanes_channel_, lane_bytes_.get(), lane_capacity_, lane_message_);
}

bool LcmPublisher::publish_status(const status_t& status) {
  // Refuse rather than overrun: the buffer was sized for texts of kStatusTextMax.
  for (const std::string* text : {&status.camera, &status.camera_problem, &status.gyro_problem, &status.instance})
    if (text->size() > kStatusTextMax) return false;
  return publish_bytes(status_channel_, status_bytes_.get(), status_capacity_, status);
}

void LcmPublisher::enable_frames(int width, int height, PixelFormat format) {
  prepare_frame_message(frame_message_, width, height, format);
  frame_bytes_.resize(static_cast<std::size_t>(frame_message_.getEncodedSize()));
}

bool LcmPublisher::publish_frame(const ImageView& image, const FrameRecord& record) {
  if (frame_bytes_.empty() || !to_frame_message(image, record, frame_message_)) return false;
  return publish_bytes(frames_channel_, frame_bytes_.data(), static_cast<int>(frame_bytes_.size()), frame_message_);
}

void LcmPublisher::set_instance(const std::string& instance) {
  instance_ = instance.substr(0, kStatusTextMax);
  lane_message_.instance = instance_;
}

void LcmPublisher::watch_for_other_instances() {
  if (watching_) return;
  for (std::string* text : {&received_.camera, &received_.camera_problem, &received_.gyro_problem, &received_.instance})
    text->reserve(kStatusTextMax + 1);
  // The C API: its handler gets the channel as a C string, where lcm-cpp's would build a
  // std::string per message (an allocation for a long prefix).
  lcm_subscribe(lcm_->getUnderlyingLCM(), status_channel_.c_str(), &LcmPublisher::on_status, this);
  watching_ = true;
}

void LcmPublisher::on_status(const lcm_recv_buf_t* rbuf, const char*, void* self) {
  auto& p = *static_cast<LcmPublisher*>(self);
  if (p.received_.decode(rbuf->data, 0, static_cast<int>(rbuf->data_size)) < 0) return;
  if (p.received_.instance == p.instance_ || p.other_seen_) return;
  p.other_seen_ = true;
  // A copy, not received_: the next status decoded overwrites that while another thread reads.
  std::snprintf(p.other_instance_, sizeof p.other_instance_, "%s", p.received_.instance.c_str());
  p.other_new_.store(true, std::memory_order_release);
}

const char* LcmPublisher::take_other_instance() {
  return other_new_.exchange(false, std::memory_order_acq_rel) ? other_instance_ : nullptr;
}

const char* LcmPublisher::poll_bus() {
  if (!watching_) return nullptr;
  while (lcm_->handleTimeout(0) > 0) {
  }
  return take_other_instance();
}

}  // namespace ccdlane
