// frame_t <-> image and record. Pixels travel in the host's byte order, which must be
// little-endian, as frame_t documents for mono16.
#include "bus/frame_message.hpp"

#include <bit>
#include <cstring>

namespace ccdlane {

static_assert(std::endian::native == std::endian::little, "frame_t carries little-endian mono16 samples");

void prepare_frame_message(frame_t& msg, int width, int height, PixelFormat format) {
  msg.utime = msg.sequence = msg.t_ns = msg.source_sequence = 0;
  msg.significant_bits = format == PixelFormat::mono16 ? 16 : 8;
  msg.has_gyro = false;
  msg.gyro_roll_deg = msg.gyro_pitch_deg = msg.gyro_yaw_deg = 0.0;
  msg.width = width;
  msg.height = height;
  msg.row_stride = width * bytes_per_pixel(format);
  msg.pixel_format = format == PixelFormat::mono16 ? frame_t::PIXEL_FORMAT_MONO16 : frame_t::PIXEL_FORMAT_MONO8;
  msg.data_size = msg.row_stride * height;
  msg.data.assign(static_cast<std::size_t>(msg.data_size), 0);
}

bool to_frame_message(const ImageView& image, const FrameRecord& record, frame_t& msg) {
  const std::int8_t format =
      image.format == PixelFormat::mono16 ? frame_t::PIXEL_FORMAT_MONO16 : frame_t::PIXEL_FORMAT_MONO8;
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
  const auto row_bytes = static_cast<std::size_t>(msg.row_stride);
  for (int y = 0; y < image.height; ++y)
    std::memcpy(msg.data.data() + static_cast<std::size_t>(y) * row_bytes, image.row(y), row_bytes);
  return true;
}

std::string frame_image(const frame_t& msg, ImageView& image) {
  const std::string frame = "frame " + std::to_string(msg.sequence) + ": ";
  if (msg.pixel_format != frame_t::PIXEL_FORMAT_MONO8 && msg.pixel_format != frame_t::PIXEL_FORMAT_MONO16)
    return frame + "unknown pixel_format " + std::to_string(msg.pixel_format);
  const PixelFormat format = msg.pixel_format == frame_t::PIXEL_FORMAT_MONO16 ? PixelFormat::mono16 : PixelFormat::mono8;
  if (msg.width < 1 || msg.height < 1) return frame + "impossible size " + std::to_string(msg.width) + "x" + std::to_string(msg.height);
  if (msg.row_stride < msg.width * bytes_per_pixel(format))
    return frame + "row_stride " + std::to_string(msg.row_stride) + " is shorter than a row";
  const auto expected = static_cast<std::int64_t>(msg.row_stride) * msg.height;
  if (msg.data_size != expected || msg.data.size() != static_cast<std::size_t>(msg.data_size))
    return frame + "data_size " + std::to_string(msg.data_size) + " is not row_stride x height = " + std::to_string(expected);
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
  return r;
}

}  // namespace ccdlane
