// Conditioned pictures over OpenCV's core and imgproc (already the tool's, for calibration
// and the annotated video): a separable Gaussian and a seeded normal generator.
#include "tools/ccdlane/picture_condition.hpp"

#include <algorithm>
#include <sstream>
#include <stdexcept>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

namespace ccdlane::cli {
namespace {

double parse_number(const std::string& key, const std::string& text) {
  std::size_t used = 0;
  double value = 0.0;
  try {
    value = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != text.size()) throw std::invalid_argument(key + "=" + text + ": not a number");
  return value;
}

void check_range(const std::string& key, double value, double low, bool low_open, double high) {
  if ((low_open ? !(value > low) : !(value >= low)) || !(value <= high)) {
    std::ostringstream what;
    what << key << "=" << value << ": outside " << (low_open ? "(" : "[") << low << ", " << high << "]";
    throw std::invalid_argument(what.str());
  }
}

int cv_type(PixelFormat format) {
  switch (format) {
    case PixelFormat::mono8: return CV_8UC1;
    case PixelFormat::mono16: return CV_16UC1;
    case PixelFormat::rgb8:
    case PixelFormat::bgr8: return CV_8UC3;
  }
  return CV_8UC1;
}

// A side of n pixels resized by `scale`.
int scaled_side(int n, double scale) { return std::max(2, static_cast<int>(std::lround(n * scale))); }

// The shadow of a bridge across the picture (PictureCondition::shade).
void shade_rows(const PictureCondition& condition, cv::Mat& levels) {
  // Full shadow between the band's edges, full light beyond them, a linear ramp across
  // the penumbra centred on each edge.
  const double height = levels.rows, soft = 0.01 * height;
  const double top = condition.shade_top * height, bottom = condition.shade_bottom * height;
  for (int y = 0; y < levels.rows; ++y) {
    const double centre = y + 0.5;
    const double in = std::clamp(std::min(centre - top, bottom - centre) / soft + 0.5, 0.0, 1.0);
    const double gain = 1.0 - in * (1.0 - condition.shade);
    if (gain != 1.0) levels.row(y) *= gain;
  }
}

}  // namespace

PictureCondition parse_picture_condition(const std::string& spec) {
  PictureCondition c;
  std::istringstream parts(spec);
  for (std::string part; std::getline(parts, part, ',');) {
    if (part.empty()) continue;
    const std::size_t eq = part.find('=');
    if (eq == std::string::npos)
      throw std::invalid_argument(part +
                                  ": not key=value (scale=TIMES, blur=PX, light=SHARE, noise=LEVELS, shade=SHARE)");
    const std::string key = part.substr(0, eq);
    const double value = parse_number(key, part.substr(eq + 1));
    if (key == "scale") {
      check_range(key, value, 0.25, false, 4.0);
      c.scale = value;
    } else if (key == "blur") {
      check_range(key, value, 0.0, false, 20.0);
      c.blur_px = value;
    } else if (key == "light") {
      check_range(key, value, 0.0, true, 4.0);
      c.light = value;
    } else if (key == "noise") {
      check_range(key, value, 0.0, false, 20.0);
      c.noise = value;
    } else if (key == "shade") {
      check_range(key, value, 0.0, true, 1.0);
      c.shade = value;
    } else if (key == "shade_top" || key == "shade_bottom") {
      check_range(key, value, 0.0, false, 1.0);
      (key == "shade_top" ? c.shade_top : c.shade_bottom) = value;
    } else {
      throw std::invalid_argument(part + ": unknown key " + key +
                                  " (scale, blur, light, noise, shade, shade_top, shade_bottom)");
    }
  }
  if (!(c.shade_top < c.shade_bottom))
    throw std::invalid_argument(spec + ": shade_top must lie above shade_bottom (shares of the height from the top)");
  return c;
}

CameraSpec camera_taking(const PictureCondition& condition, const CameraSpec& camera) {
  if (condition.scale == 1.0) return camera;
  const double s = condition.scale;
  CameraSpec c = camera;
  c.Nu = scaled_side(camera.Nu, s);
  c.Nv = scaled_side(camera.Nv, s);
  // Pixels as far apart on the chip as the resize puts them, whatever the rounding of
  // their count: the cell size that makes the pixel pitch (U - Uc) / (Nu - 1) 1/su of it.
  const double su = static_cast<double>(c.Nu) / camera.Nu, sv = static_cast<double>(c.Nv) / camera.Nv;
  c.Uc_mm = camera.U_mm - camera.pitch_u() / su * (c.Nu - 1);
  c.Vc_mm = camera.V_mm - camera.pitch_v() / sv * (c.Nv - 1);
  c.cx = (camera.cx - 0.5) * su + 0.5;
  c.cy = (camera.cy - 0.5) * sv + 0.5;
  c.k_px2 = camera.k_px2 / (su * sv);
  return c;
}

ImageView PictureConditioner::apply(const ImageView& frame, std::uint64_t frame_number) {
  if (condition_.identity() || frame.empty()) return frame;
  const int type = cv_type(frame.format);
  const cv::Mat in(frame.height, frame.width, type, const_cast<std::uint8_t*>(frame.data),
                   static_cast<std::size_t>(frame.stride_bytes));
  cv::Mat levels;
  in.convertTo(levels, CV_32F);
  const int width = scaled_side(frame.width, condition_.scale), height = scaled_side(frame.height, condition_.scale);
  if (condition_.scale != 1.0)
    cv::resize(levels, levels, cv::Size(width, height), 0.0, 0.0,
               condition_.scale < 1.0 ? cv::INTER_AREA : cv::INTER_LINEAR);
  if (condition_.blur_px > 0.0)
    cv::GaussianBlur(levels, levels, cv::Size(0, 0), condition_.blur_px, condition_.blur_px, cv::BORDER_REPLICATE);
  levels *= condition_.light;
  if (condition_.shade != 1.0) shade_rows(condition_, levels);
  // 8-bit levels in the frame's own: a 12-bit mono16 frame's level is 4095 / 255 of them.
  const double max_level = frame.format == PixelFormat::mono16 ? (1 << frame.significant_bits) - 1 : 255;
  if (condition_.noise > 0.0) {
    cv::Mat noise(levels.size(), levels.type());
    cv::RNG generator(frame_number * 0x9E3779B97F4A7C15ull + 1u);
    generator.fill(noise, cv::RNG::NORMAL, 0.0, condition_.noise * max_level / 255.0);
    levels += noise;
  }
  levels = cv::min(levels, max_level);
  const int bpp = bytes_per_pixel(frame.format);
  pixels_.resize(static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * static_cast<std::size_t>(bpp));
  cv::Mat out(height, width, type, pixels_.data());
  levels.convertTo(out, type);  // rounded, negative levels to 0
  return {pixels_.data(), width, height, width * bpp, frame.format, frame.significant_bits};
}

}  // namespace ccdlane::cli
