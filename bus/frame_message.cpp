// frame_t <-> image and record. Pixels travel in the host's byte order, which must be
// little-endian, as frame_t documents for mono16.
#include "bus/frame_message.hpp"

#include <bit>
#include <cmath>
#include <cstring>

namespace ccdlane {

static_assert(std::endian::native == std::endian::little, "frame_t carries little-endian mono16 samples");
static_assert(frame_t::TURN_INDICATOR_NONE == static_cast<int>(TurnIndicator::none));
static_assert(frame_t::TURN_INDICATOR_LEFT == static_cast<int>(TurnIndicator::left));
static_assert(frame_t::TURN_INDICATOR_RIGHT == static_cast<int>(TurnIndicator::right));
static_assert(frame_t::TURN_INDICATOR_BOTH == static_cast<int>(TurnIndicator::both));

namespace {

std::int8_t wire_format(PixelFormat f) {
  switch (f) {
    case PixelFormat::mono8: return frame_t::PIXEL_FORMAT_MONO8;
    case PixelFormat::mono16: return frame_t::PIXEL_FORMAT_MONO16;
    case PixelFormat::rgb8: return frame_t::PIXEL_FORMAT_RGB8;
    case PixelFormat::bgr8: return frame_t::PIXEL_FORMAT_BGR8;
  }
  return -1;
}

std::optional<PixelFormat> image_format(std::int8_t f) {
  switch (f) {
    case frame_t::PIXEL_FORMAT_MONO8: return PixelFormat::mono8;
    case frame_t::PIXEL_FORMAT_MONO16: return PixelFormat::mono16;
    case frame_t::PIXEL_FORMAT_RGB8: return PixelFormat::rgb8;
    case frame_t::PIXEL_FORMAT_BGR8: return PixelFormat::bgr8;
    default: return std::nullopt;
  }
}

}  // namespace

void prepare_frame_message(frame_t& msg, int width, int height, PixelFormat format) {
  msg.utime = msg.sequence = msg.t_ns = msg.source_sequence = 0;
  msg.significant_bits = format == PixelFormat::mono16 ? 16 : 8;
  msg.has_gyro = false;
  msg.gyro_roll_deg = msg.gyro_pitch_deg = msg.gyro_yaw_deg = 0.0;
  msg.has_speed = msg.has_yaw_rate = false;
  msg.speed_kmh = msg.yaw_rate_radps = 0.0;
  msg.turn_indicator = frame_t::TURN_INDICATOR_NONE;
  msg.width = width;
  msg.height = height;
  msg.row_stride = width * bytes_per_pixel(format);
  msg.pixel_format = wire_format(format);
  msg.data_size = msg.row_stride * height;
  msg.data.assign(static_cast<std::size_t>(msg.data_size), 0);
}

bool to_frame_message(const ImageView& image, const FrameRecord& record, frame_t& msg) {
  const std::int8_t format = wire_format(image.format);
  if (image.width != msg.width || image.height != msg.height || format != msg.pixel_format ||
      msg.data.size() != static_cast<std::size_t>(msg.data_size))
    return false;
  msg.utime = record.utime;
  msg.sequence = static_cast<std::int64_t>(record.sequence);
  msg.source_sequence = static_cast<std::int64_t>(record.source_sequence);
  msg.t_ns = record.t_ns;
  msg.significant_bits = static_cast<std::int8_t>(image.significant_bits);
  msg.has_gyro = record.gyro.has_value();
  msg.gyro_roll_deg = record.gyro ? record.gyro->roll_deg : 0.0;
  msg.gyro_pitch_deg = record.gyro ? record.gyro->pitch_deg : 0.0;
  msg.gyro_yaw_deg = record.gyro ? record.gyro->yaw_deg : 0.0;
  msg.has_speed = record.speed_kmh.has_value();
  msg.speed_kmh = record.speed_kmh.value_or(0.0);
  msg.has_yaw_rate = record.yaw_rate_radps.has_value();
  msg.yaw_rate_radps = record.yaw_rate_radps.value_or(0.0);
  msg.turn_indicator = static_cast<std::int8_t>(record.indicator);
  const auto row_bytes = static_cast<std::size_t>(msg.row_stride);
  for (int y = 0; y < image.height; ++y)
    std::memcpy(msg.data.data() + static_cast<std::size_t>(y) * row_bytes, image.row(y), row_bytes);
  return true;
}

std::string frame_image(const frame_t& msg, ImageView& image) {
  const std::string frame = "frame " + std::to_string(msg.sequence) + ": ";
  const std::optional<PixelFormat> known = image_format(msg.pixel_format);
  if (!known) return frame + "unknown pixel_format " + std::to_string(msg.pixel_format);
  const PixelFormat format = *known;
  if (msg.width < 1 || msg.height < 1)
    return frame + "impossible size " + std::to_string(msg.width) + "x" + std::to_string(msg.height);
  if (msg.row_stride < msg.width * bytes_per_pixel(format))
    return frame + "row_stride " + std::to_string(msg.row_stride) + " is shorter than a row";
  const auto expected = static_cast<std::int64_t>(msg.row_stride) * msg.height;
  if (msg.data_size != expected || msg.data.size() != static_cast<std::size_t>(msg.data_size))
    return frame + "data_size " + std::to_string(msg.data_size) +
           " is not row_stride x height = " + std::to_string(expected);
  const int max_bits = format == PixelFormat::mono16 ? 16 : 8;
  const int min_bits = format == PixelFormat::mono16 ? 9 : 8;
  if (msg.significant_bits < min_bits || msg.significant_bits > max_bits)
    return frame + "significant_bits " + std::to_string(msg.significant_bits) + " is impossible for its pixel_format";
  image = ImageView{msg.data.data(), msg.width, msg.height, msg.row_stride, format, msg.significant_bits};
  return "";
}

FrameRecord frame_record(const frame_t& msg) {
  FrameRecord r;
  r.sequence = static_cast<std::uint64_t>(msg.sequence);
  r.source_sequence = static_cast<std::uint64_t>(msg.source_sequence);
  r.t_ns = msg.t_ns;
  r.utime = msg.utime;
  if (msg.has_gyro) r.gyro = Gx1Angles{msg.gyro_roll_deg, msg.gyro_pitch_deg, msg.gyro_yaw_deg};
  if (msg.has_speed && std::isfinite(msg.speed_kmh) && msg.speed_kmh >= 0.0) r.speed_kmh = msg.speed_kmh;
  if (msg.has_yaw_rate && std::isfinite(msg.yaw_rate_radps)) r.yaw_rate_radps = msg.yaw_rate_radps;
  // An unknown code (a newer publisher) is no indicator, not a guess.
  if (msg.turn_indicator >= frame_t::TURN_INDICATOR_NONE && msg.turn_indicator <= frame_t::TURN_INDICATOR_BOTH)
    r.indicator = static_cast<TurnIndicator>(msg.turn_indicator);
  return r;
}

}  // namespace ccdlane
