// Frame directory source: pacing on CLOCK_MONOTONIC with absolute sleeps, so decode time
// does not accumulate into drift.
#include "drivers/frames/frame_directory_source.hpp"

#include <time.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>

#include "drivers/device_state.hpp"

namespace ccdlane {
namespace {

constexpr std::int64_t kDefaultPeriodNs = 33'333'333;  // 30 Hz when nothing says otherwise

}  // namespace

FrameDirectorySource::FrameDirectorySource(FrameDirectorySourceOptions options) : options_(std::move(options)) {}

FrameDirectorySource::~FrameDirectorySource() = default;

void FrameDirectorySource::set_problem(std::string_view text) {
  const std::size_t n = std::min(text.size(), problem_.size() - 1);
  std::memcpy(problem_.data(), text.data(), n);
  problem_[n] = '\0';
}

std::string FrameDirectorySource::open() {
  try {
    directory_ = std::make_unique<FrameDirectory>(options_.path);
  } catch (const FrameDirectoryError& e) {
    return e.what();
  }
  FrameDirectory& dir = *directory_;
  if (dir.size() == 0) return dir.csv_path() + ": no usable frame rows";
  const auto header = dir.probe_first();
  if (!header)
    return dir.path() + ": none of the " + std::to_string(dir.size()) + " frames can be read (" +
           std::string(dir.error()) + ")";
  if (options_.width > 0 && (header->width != options_.width || header->height != options_.height))
    return dir.path() + ": frames are " + std::to_string(header->width) + "x" + std::to_string(header->height) +
           ", the camera is " + std::to_string(options_.width) + "x" + std::to_string(options_.height);
  width_ = header->width;
  height_ = header->height;
  format_ = header->format();
  significant_bits_ = header->format() == PixelFormat::mono16 ? header->significant_bits() : 8;
  if (options_.rate_hz > 0.0) {
    period_ns_ = static_cast<std::int64_t>(1e9 / options_.rate_hz);
  } else if (dir.size() >= 2) {
    period_ns_ = (dir.row(dir.size() - 1).t_ns - dir.row(0).t_ns) / static_cast<std::int64_t>(dir.size() - 1);
  }
  if (period_ns_ <= 0) period_ns_ = kDefaultPeriodNs;
  // A loop's next pass is stamped as if the recording went on: one recorded mean period
  // after its last frame, so that frame times never go backwards.
  const std::int64_t span = dir.row(dir.size() - 1).t_ns - dir.row(0).t_ns;
  const std::int64_t recorded_period = dir.size() >= 2 ? span / static_cast<std::int64_t>(dir.size() - 1) : 0;
  pass_span_ns_ = span + (recorded_period > 0 ? recorded_period : kDefaultPeriodNs);
  next_ = 0;
  pass_ = 0;
  started_ = false;
  return "";
}

CaptureStatus FrameDirectorySource::capture(const MutableImageView& into, FrameMeta& meta, int timeout_ms) {
  if (!directory_) return CaptureStatus::end_of_stream;
  FrameDirectory& dir = *directory_;
  if (next_ >= dir.size()) {
    if (!options_.loop) return CaptureStatus::end_of_stream;
    next_ = 0;
    ++pass_;
    next_due_ns_ += period_ns_;
  }
  const std::int64_t now = monotonic_ns();
  if (!started_) {
    started_ = true;
    next_due_ns_ = now;
  }
  if (now > next_due_ns_ + period_ns_) next_due_ns_ = now;  // fell behind: re-anchor, don't burst
  if (!sleep_until_due(next_due_ns_, timeout_ms)) {
    ++counters_.timeouts;
    return CaptureStatus::timeout;
  }

  const std::size_t i = next_++;
  meta.sequence = pass_ * dir.data_rows() + dir.row(i).index;
  meta.t_ns = monotonic_ns();
  meta.recorded_t_ns = dir.row(i).t_ns + static_cast<std::int64_t>(pass_) * pass_span_ns_;
  meta.gyro = dir.row(i).gyro;
  meta.speed_kmh = dir.row(i).speed_kmh;
  meta.indicator = dir.has_vehicle_columns() ? std::optional<TurnIndicator>(dir.row(i).indicator) : std::nullopt;
  // When this frame's successor is due (after the last row, the wrap adds one period).
  if (next_ < dir.size())
    next_due_ns_ +=
        options_.rate_hz > 0.0 ? period_ns_ : std::max<std::int64_t>(0, dir.row(next_).t_ns - dir.row(i).t_ns);

  if (dir.read(i, into) != PgmFault::none) {
    ++counters_.errors;
    set_problem(dir.error());
    return CaptureStatus::error;
  }
  ++counters_.frames;
  return CaptureStatus::frame;
}

void FrameDirectorySource::close() { directory_.reset(); }

std::string FrameDirectorySource::describe() const {
  char buf[64];
  if (options_.rate_hz > 0.0)
    std::snprintf(buf, sizeof buf, "%.3g Hz", options_.rate_hz);
  else if (directory_ && !directory_->note().empty())  // a folder of pictures: no times recorded
    std::snprintf(buf, sizeof buf, "in name order at %.3g Hz", 1e9 / FrameDirectory::kPictureFolderFrameNs);
  else
    std::snprintf(buf, sizeof buf, "as recorded");
  return "frames:" + options_.path + " " + std::to_string(width_) + "x" + std::to_string(height_) +
         (format_ == PixelFormat::mono16 ? " mono16 "
          : is_colour(format_)           ? " rgb8 "
                                         : " mono8 ") +
         buf + (options_.loop ? " loop" : "");
}

std::string FrameDirectorySource::last_problem() const { return problem_.data(); }

}  // namespace ccdlane
