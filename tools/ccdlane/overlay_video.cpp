// Annotated video frames drawn with OpenCV's imgproc (filled polygons, antialiased lines,
// text), which the tool already links for `calibrate camera`.
#include "tools/ccdlane/overlay_video.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "tools/ccdlane/overlay_png.hpp"
#include "tools/ccdlane/radius_text.hpp"
#include "tools/ccdlane/road_line_picture.hpp"

namespace ccdlane::cli {
namespace {

const cv::Scalar kLane(40, 220, 90), kMark(255, 255, 255), kText(255, 255, 255), kWarning(255, 30, 30);
const cv::Scalar kLineColours[] = {{255, 200, 0}, {0, 200, 255}, {255, 90, 255}, {120, 255, 120}};

std::vector<cv::Point> line_points(const CameraModel& camera, const RoadLine& l, const Config& config) {
  std::vector<cv::Point> points;
  for (const std::optional<Vec2>& p :
       road_line_pixels(camera, l, config.detection.min_range_mm, config.detection.max_range_mm, 40))
    if (p) points.emplace_back(static_cast<int>(std::lround(p->x() - 1)), static_cast<int>(std::lround(p->y() - 1)));
  return points;
}

// The own lane: the nearest line on each side of the vehicle (largest y0 first).
std::optional<std::pair<int, int>> own_lane(const SolveResult& s) {
  int left = -1, right = -1;
  for (int j = 0; j < s.num_lines; ++j) {
    const double y0 = s.lines[static_cast<std::size_t>(j)].y0_mm;
    if (y0 > 0) left = j;
    if (y0 < 0 && right < 0) right = j;
  }
  if (left < 0 || right < 0) return std::nullopt;
  return std::pair{left, right};
}

// Faint: the marks detection considered and the own lane, blended into the picture.
void draw_faint(cv::Mat& picture, const LaneEstimator& estimator, const CameraModel* camera, const Config& config) {
  cv::Mat layer = picture.clone();
  for (const MarkCandidate& m : estimator.detection().marks)
    cv::line(layer, {static_cast<int>(m.left_px - 1), static_cast<int>(m.py - 1)},
             {static_cast<int>(m.right_px - 1), static_cast<int>(m.py - 1)}, kMark, 2);
  if (const SolveResult* s = estimator.solution(); camera && s)
    if (const auto lane = own_lane(*s)) {
      std::vector<cv::Point> polygon = line_points(*camera, s->lines[static_cast<std::size_t>(lane->first)], config);
      std::vector<cv::Point> right = line_points(*camera, s->lines[static_cast<std::size_t>(lane->second)], config);
      polygon.insert(polygon.end(), right.rbegin(), right.rend());
      if (polygon.size() >= 3) cv::fillPoly(layer, std::vector<std::vector<cv::Point>>{polygon}, kLane);
    }
  cv::addWeighted(layer, 0.35, picture, 0.65, 0.0, picture);
}

void draw_warning(cv::Mat& picture, ldw::Side side, int strip_top) {
  if (side == ldw::Side::none) return;
  const int w = picture.cols, bar = std::max(12, w / 50);
  const bool left = side == ldw::Side::left;
  cv::rectangle(picture, {left ? 0 : w - bar, 0}, {left ? bar : w, strip_top}, kWarning, cv::FILLED);
  const double scale = w / 1280.0 * 1.4;
  const std::string text = left ? "<< LANE DEPARTURE" : "LANE DEPARTURE >>";
  int baseline = 0;
  const cv::Size size = cv::getTextSize(text, cv::FONT_HERSHEY_SIMPLEX, scale, 3, &baseline);
  cv::putText(picture, text, {left ? 2 * bar : w - 2 * bar - size.width, size.height + 2 * bar},
              cv::FONT_HERSHEY_SIMPLEX, scale, kWarning, 3, cv::LINE_AA);
}

}  // namespace

std::string overlay_strip_text(const LaneEstimate& e) {
  char text[256];
  const LdwEstimate& l = e.ldw;
  const std::string ldw =
      l.available ? std::string("LDW available") : std::string("LDW unavailable (") + to_string(l.reason) + ")";
  const std::string state = std::string(e.ok ? "ok" : to_string(e.reason)) + ", " + ldw::to_string(l.track);
  if (e.ok)
    std::snprintf(
        text, sizeof text, "width %.2f m | offset %+.2f m | heading %+.1f deg | radius %s | %s | %s",
        e.lane_width_mm / 1000.0, e.lateral_offset_mm / 1000.0, e.heading_deg,
        radius_text(e.curvature_per_m != 0.0 ? 1.0 / e.curvature_per_m : std::numeric_limits<double>::infinity())
            .c_str(),
        state.c_str(), ldw.c_str());
  else
    std::snprintf(text, sizeof text, "width - | offset - | heading - | radius - | %s | %s", state.c_str(), ldw.c_str());
  return text;
}

OverlayVideo::OverlayVideo(const std::string& path, int width, int height, int time_base_num, int time_base_den)
    : writer_(path,
              {.width = width, .height = height, .time_base_num = time_base_num, .time_base_den = time_base_den}) {}

void OverlayVideo::add(const ImageView& frame, const LaneEstimate& e, const LaneEstimator& estimator,
                       const Config& config) {
  const Overlay background(frame);  // the frame as RGB, whatever it was
  const ImageView rgb = background.view();
  cv::Mat picture(rgb.height, rgb.width, CV_8UC3);
  for (int y = 0; y < rgb.height; ++y) std::copy_n(rgb.row(y), 3 * rgb.width, picture.ptr<std::uint8_t>(y));
  const SolveResult* s = estimator.solution();
  std::optional<CameraModel> camera;
  if (s && s->converged) camera.emplace(config.camera, s->pose);
  draw_faint(picture, estimator, camera ? &*camera : nullptr, config);
  if (camera)
    for (int j = 0; j < s->num_lines; ++j)
      cv::polylines(picture,
                    std::vector<std::vector<cv::Point>>{line_points(*camera, s->lines[std::size_t(j)], config)}, false,
                    kLineColours[j % 4], 3, cv::LINE_AA);
  const double scale = rgb.width / 1280.0 * 0.62;
  const int strip = std::max(18, static_cast<int>(34 * rgb.width / 1280.0));
  const int strip_top = rgb.height - strip;
  cv::rectangle(picture, {0, strip_top}, {rgb.width, rgb.height}, cv::Scalar(0, 0, 0), cv::FILLED);
  cv::putText(picture, overlay_strip_text(e), {8, rgb.height - strip / 3}, cv::FONT_HERSHEY_SIMPLEX, scale, kText, 1,
              cv::LINE_AA);
  draw_warning(picture, e.ldw.warning, strip_top);
  writer_.write(
      ImageView{picture.data, rgb.width, rgb.height, static_cast<std::ptrdiff_t>(picture.step), PixelFormat::rgb8, 8},
      e.t_ns);
}

}  // namespace ccdlane::cli
