// Video source: decodes one frame ahead, then paces on CLOCK_MONOTONIC with absolute
// sleeps, so that decode time does not accumulate into drift.
#include "drivers/frames/video_source.hpp"

#include <cstring>

#include "base/clock.hpp"

namespace ccdlane {

VideoSource::VideoSource(VideoSourceOptions options) : options_(std::move(options)) {}

VideoSource::~VideoSource() = default;

std::string VideoSource::open() {
  try {
    reader_ = std::make_unique<VideoReader>(options_.path);
  } catch (const std::runtime_error& e) {  // VideoError, or FFmpeg out of memory
    return e.what();
  }
  const VideoReader& r = *reader_;
  if (options_.width > 0 && (r.width() != options_.width || r.height() != options_.height)) {
    const std::string why = r.path() + ": frames are " + std::to_string(r.width()) + "x" + std::to_string(r.height()) +
                            ", the camera is " + std::to_string(options_.width) + "x" + std::to_string(options_.height);
    reader_.reset();
    return why;
  }
  staged_ = std::make_unique<ImageBuffer>(r.width(), r.height(), r.format(), 8);
  if (r.frame_rate_hz() > 0.0) period_ns_ = static_cast<std::int64_t>(1e9 / r.frame_rate_hz());
  have_staged_ = started_ = false;
  pass_offset_ns_ = last_t_ns_ = 0;
  sequence_ = 0;
  return "";
}

CaptureStatus VideoSource::decode_ahead() {
  std::int64_t t_ns = 0;
  for (int attempt = 0; attempt < 2; ++attempt) {
    const VideoRead got = reader_->next(staged_->view(), t_ns);
    if (got == VideoRead::frame) {
      staged_t_ns_ = pass_offset_ns_ + t_ns;
      have_staged_ = true;
      return CaptureStatus::frame;
    }
    if (got == VideoRead::damaged && problem_.empty()) {
      problem_.set("%.*s", static_cast<int>(reader_->problem().size()), reader_->problem().data());
      ++counters_.errors;
      return CaptureStatus::error;
    }
    // The end (or the damage already reported): start over when looping, one period on.
    if (!options_.loop || reader_->frames_read() == 0 || !reader_->rewind()) return CaptureStatus::end_of_stream;
    pass_offset_ns_ = last_t_ns_ + period_ns_;
    problem_.clear();
  }
  return CaptureStatus::end_of_stream;
}

CaptureStatus VideoSource::capture(const MutableImageView& into, FrameMeta& meta, int timeout_ms) {
  if (!reader_) return CaptureStatus::end_of_stream;
  if (!have_staged_)
    if (const CaptureStatus s = decode_ahead(); s != CaptureStatus::frame) return s;
  const std::int64_t now = monotonic_ns();
  if (!started_) {
    started_ = true;
    anchor_ns_ = now - staged_t_ns_;
  }
  std::int64_t due = anchor_ns_ + staged_t_ns_;
  if (now > due + period_ns_) anchor_ns_ += now - due, due = now;  // fell behind: re-anchor, don't burst
  if (!sleep_until_due(due, timeout_ms)) {
    ++counters_.timeouts;
    return CaptureStatus::timeout;
  }
  const ImageView from = staged_->view();
  for (int y = 0; y < from.height; ++y)
    std::memcpy(into.row(y), from.row(y), static_cast<std::size_t>(from.width) * bytes_per_pixel(from.format));
  have_staged_ = false;
  meta.sequence = sequence_++;
  meta.t_ns = monotonic_ns();
  meta.recorded_t_ns = staged_t_ns_;
  last_t_ns_ = staged_t_ns_;
  meta.gyro.reset();
  meta.speed_kmh.reset();
  meta.indicator.reset();
  ++counters_.frames;
  return CaptureStatus::frame;
}

void VideoSource::close() {
  reader_.reset();
  staged_.reset();
  have_staged_ = false;
}

std::string VideoSource::describe() const {
  if (!reader_) return "video:" + options_.path;
  char rate[32];
  std::snprintf(rate, sizeof rate, "%.3g fps", reader_->frame_rate_hz());
  return "video:" + options_.path + " " + std::to_string(reader_->width()) + "x" + std::to_string(reader_->height()) +
         " " + reader_->codec() + (reader_->format() == PixelFormat::mono8 ? " mono8 " : " rgb8 ") + rate +
         " as recorded" + (options_.loop ? " loop" : "");
}

}  // namespace ccdlane
