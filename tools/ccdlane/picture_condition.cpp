// Conditioned pictures over OpenCV's core and imgproc (already the tool's, for calibration
// and the annotated video): a separable Gaussian and a seeded normal generator.
#include "tools/ccdlane/picture_condition.hpp"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <sstream>
#include <stdexcept>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "tools/ccdlane/jpeg_round_trip.hpp"

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

// The trees' shadows (PictureCondition::dapple) as a field over a stretch of road three
// pictures tall that repeats (the picture's rows go round it as it drifts, without a
// seam): 1 in shadow, 0 in sun, soft between. Smooth random patches (a coarse grid of
// normal values, blurred wider across than along, thresholded at the cover's quantile),
// the threshold's edge blurred as the penumbra: the sun's half degree from a crown 5-10 m
// up is 5-9 cm on the road, a few pixels 10 m ahead (a sigma of a tenth of a percent of
// the width). The grid is laid three times over and the middle taken, so that its blurs
// see the same patches beyond either end as the other end holds. Seeded once: the same
// trees for every frame of a replay.
std::vector<float> dapple_field(int width, int height, double cover) {
  const int field_height = 3 * height;
  cv::Mat coarse(std::max(4, field_height / 12), std::max(4, width / 24), CV_32F);
  cv::RNG generator(0x7EE5ull);
  generator.fill(coarse, cv::RNG::NORMAL, 0.0, 1.0);
  cv::Mat repeated, field;
  cv::vconcat(std::vector<cv::Mat>{coarse, coarse, coarse}, repeated);
  cv::resize(repeated, field, cv::Size(width, 3 * field_height), 0.0, 0.0, cv::INTER_CUBIC);
  cv::GaussianBlur(field, field, cv::Size(0, 0), 0.03 * width, 0.012 * height, cv::BORDER_REFLECT);
  // The middle stretch's values: whole rows of a continuous matrix, one run of floats.
  const auto middle = [&] {
    const float* first = field.ptr<float>(field_height);
    return std::vector<float>(first, first + static_cast<std::ptrdiff_t>(width) * field_height);
  };
  std::vector<float> values = middle();
  const auto quantile = static_cast<std::ptrdiff_t>((1.0 - cover) * static_cast<double>(values.size()));
  std::nth_element(values.begin(), values.begin() + quantile, values.end());
  const float threshold = values[static_cast<std::size_t>(quantile)];
  cv::Mat shadow = field > threshold;  // 255 in shadow
  shadow.convertTo(field, CV_32F, 1.0 / 255.0);
  cv::GaussianBlur(field, field, cv::Size(0, 0), 0.001 * width + 0.5, 0.001 * width + 0.5, cv::BORDER_REFLECT);
  return middle();
}

// The trees' shadows on the lower half of the picture (the road ahead; the sky and the
// trees' crowns above are left), fading in over its first 6 % of the height (no edge
// straight across the picture that trees would not cast), the field moved down 1 % of
// the height a frame.
void dapple_rows(const PictureCondition& condition, const std::vector<float>& field, std::uint64_t frame_number,
                 cv::Mat& levels) {
  const int field_height = static_cast<int>(field.size() / static_cast<std::size_t>(levels.cols));
  const int drift = static_cast<int>(static_cast<std::uint64_t>(std::lround(0.01 * levels.rows) + 1) * frame_number %
                                     static_cast<std::uint64_t>(field_height));
  const int channels = levels.channels();
  for (int y = levels.rows / 2; y < levels.rows; ++y) {
    const float* shadow = field.data() + static_cast<std::size_t>((y - drift + field_height) % field_height) *
                                             static_cast<std::size_t>(levels.cols);
    const double fade = std::min(1.0, (y + 0.5 - 0.5 * levels.rows) / (0.06 * levels.rows));
    const auto depth = static_cast<float>(fade * (1.0 - condition.dapple));
    float* row = levels.ptr<float>(y);
    for (int x = 0; x < levels.cols; ++x) {
      const float gain = 1.0f - shadow[x] * depth;
      for (int k = 0; k < channels; ++k) row[x * channels + k] *= gain;
    }
  }
}

// Each key, its field and the values it takes: [low, high], or (low, high] when
// `low_open`; in this order in the error that names an unknown key.
struct ConditionKey {
  const char* key;
  double PictureCondition::*field;
  double low;
  bool low_open;
  double high;
};
constexpr ConditionKey kConditionKeys[] = {
    {"scale", &PictureCondition::scale, 0.25, false, 4.0},
    {"blur", &PictureCondition::blur_px, 0.0, false, 20.0},
    {"light", &PictureCondition::light, 0.0, true, 4.0},
    {"noise", &PictureCondition::noise, 0.0, false, 20.0},
    {"shade", &PictureCondition::shade, 0.0, true, 1.0},
    {"shade_top", &PictureCondition::shade_top, 0.0, false, 1.0},
    {"shade_bottom", &PictureCondition::shade_bottom, 0.0, false, 1.0},
    {"dapple", &PictureCondition::dapple, 0.0, true, 1.0},
    {"dapple_cover", &PictureCondition::dapple_cover, 0.05, false, 0.95},
    {"jpeg", &PictureCondition::jpeg, 1.0, false, 100.0},
};

}  // namespace

PictureCondition parse_picture_condition(const std::string& spec) {
  PictureCondition c;
  std::istringstream parts(spec);
  for (std::string part; std::getline(parts, part, ',');) {
    if (part.empty()) continue;
    const std::size_t eq = part.find('=');
    if (eq == std::string::npos)
      throw std::invalid_argument(
          part +
          ": not key=value (scale=TIMES, blur=PX, light=SHARE, noise=LEVELS, shade=SHARE, dapple=SHARE, jpeg=QUALITY)");
    const std::string key = part.substr(0, eq);
    const double value = parse_number(key, part.substr(eq + 1));
    const auto known = std::find_if(std::begin(kConditionKeys), std::end(kConditionKeys),
                                    [&](const ConditionKey& k) { return key == k.key; });
    if (known == std::end(kConditionKeys)) {
      std::string keys;
      for (const ConditionKey& k : kConditionKeys) keys += (keys.empty() ? "" : ", ") + std::string(k.key);
      throw std::invalid_argument(part + ": unknown key " + key + " (" + keys + ")");
    }
    check_range(key, value, known->low, known->low_open, known->high);
    c.*(known->field) = value;
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
  if (condition_.dapple != 1.0) {
    if (dapple_width_ != width || dapple_height_ != height)
      dapple_field_ = dapple_field(width, height, condition_.dapple_cover), dapple_width_ = width,
      dapple_height_ = height;
    dapple_rows(condition_, dapple_field_, frame_number, levels);
  }
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
  if (condition_.jpeg > 0.0) {
    std::string error;
    if (!jpeg_round_trip(pixels_.data(), width, height, frame.format, static_cast<int>(std::lround(condition_.jpeg)),
                         error))
      throw std::runtime_error("jpeg=: libjpeg: " + error);
  }
  return {pixels_.data(), width, height, width * bpp, frame.format, frame.significant_bits};
}

}  // namespace ccdlane::cli
