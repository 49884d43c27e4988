// TuSimple-style scoring: lane points per mask row, reported lines projected onto the
// same rows, hits within a width-scaled threshold.
#include "tools/ccdlane/lane_score.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>

#include "tools/ccdlane/road_line_picture.hpp"

namespace ccdlane::cli {

std::vector<AnnotatedLane> lanes_of_mask(const ImageView& mask) {
  // Per level: the sum of columns and the count on the current row.
  std::map<int, AnnotatedLane> by_level;
  std::vector<double> sum(256), count(256);
  for (int y = 0; y < mask.height; ++y) {
    std::fill(sum.begin(), sum.end(), 0.0);
    std::fill(count.begin(), count.end(), 0.0);
    const std::uint8_t* row = mask.row(y);
    for (int x = 0; x < mask.width; ++x)
      if (row[x] != 0) sum[row[x]] += x + 1, count[row[x]] += 1.0;
    for (int level = 1; level < 256; ++level)
      if (count[static_cast<std::size_t>(level)] > 0.0) {
        AnnotatedLane& lane = by_level[level];
        lane.level = level;
        lane.points.emplace_back(sum[static_cast<std::size_t>(level)] / count[static_cast<std::size_t>(level)], y + 1);
      }
  }
  std::vector<AnnotatedLane> out;
  for (auto& [level, lane] : by_level) out.push_back(std::move(lane));
  mark_ego_lanes(out, mask.width, mask.height);
  return out;
}

namespace {

// The least-squares line x = mean_x + slope (y - mean_y) through points; slope 0 when
// they all lie on one row.
struct LineXOnY {
  double mean_x = 0.0, mean_y = 0.0, slope = 0.0;
  bool sloped = false;  // the points span more than one row
};

LineXOnY fit_x_on_y(std::span<const Vec2> points) {
  const auto n = static_cast<double>(points.size());
  double sy = 0, sx = 0, syy = 0, sxy = 0;
  for (const Vec2& p : points) sy += p.y(), sx += p.x(), syy += p.y() * p.y(), sxy += p.x() * p.y();
  LineXOnY l{sx / n, sy / n, 0.0, false};
  const double var = syy - sy * sy / n;
  if (var > 0.0) l.slope = (sxy - sx * sy / n) / var, l.sloped = true;
  return l;
}

}  // namespace

double tusimple_threshold_scale(const AnnotatedLane& lane) {
  if (lane.points.size() < 2) return 1.0;
  const LineXOnY l = fit_x_on_y(lane.points);
  return l.sloped ? 1.0 / std::cos(std::atan(l.slope)) : 1.0;
}

void mark_ego_lanes(std::span<AnnotatedLane> lanes, int width, int height) {
  const double centre = 0.5 * (width + 1);
  int left = -1, right = -1;
  double left_x = -1e300, right_x = 1e300;
  for (std::size_t k = 0; k < lanes.size(); ++k) {
    AnnotatedLane& lane = lanes[k];
    lane.ego = false;
    if (lane.points.size() < 2) continue;
    // A straight line through the lowest third of the lane's points (at least two).
    std::vector<Vec2> pts = lane.points;
    std::sort(pts.begin(), pts.end(), [](const Vec2& a, const Vec2& b) { return a.y() > b.y(); });
    const LineXOnY l = fit_x_on_y(std::span<const Vec2>(pts).first(std::max<std::size_t>(2, pts.size() / 3)));
    const double x_bottom = l.mean_x + l.slope * (height - l.mean_y);
    lane.x_bottom = x_bottom;
    if (x_bottom < centre && x_bottom > left_x) left_x = x_bottom, left = static_cast<int>(k);
    if (x_bottom >= centre && x_bottom < right_x) right_x = x_bottom, right = static_cast<int>(k);
  }
  if (left >= 0) lanes[static_cast<std::size_t>(left)].ego = true;
  if (right >= 0) lanes[static_cast<std::size_t>(right)].ego = true;
}

FrameScore& FrameScore::operator+=(const FrameScore& o) {
  lanes += o.lanes;
  found += o.found;
  reported += o.reported;
  false_lines += o.false_lines;
  points += o.points;
  hit_points += o.hit_points;
  ego_lanes += o.ego_lanes;
  ego_found += o.ego_found;
  ego_points += o.ego_points;
  ego_hit_points += o.ego_hit_points;
  return *this;
}

namespace {

// A line's column on a row (1-based), where it crosses the row within the picture.
std::optional<double> column_in_picture(const CameraModel& camera, const RoadLine& line, double row, int width,
                                        const ScoreRules& rules) {
  const std::optional<double> x = road_line_column_at_row(camera, line, row, rules.near_mm, rules.far_mm);
  if (x && *x >= 0.5 && *x <= width + 0.5) return x;
  return std::nullopt;
}

}  // namespace

FrameScore score_frame(std::span<const AnnotatedLane> lanes, int width, const CameraModel& camera,
                       std::span<const RoadLine> lines, const ScoreRules& rules, LanePointHits* point_hits,
                       std::vector<ReportedLineResult>* line_results) {
  const double threshold = ScoreRules::threshold_for_width(rules.threshold_px, width);
  FrameScore score;
  if (point_hits) point_hits->assign(lanes.size(), {});
  score.lanes = static_cast<int>(lanes.size());
  // Every row some lane covers, with that lane's centre and threshold: a line's points
  // are sampled there.
  struct LanePoint {
    double x, threshold;
  };
  std::map<int, std::vector<LanePoint>> lane_columns_by_row;
  for (const AnnotatedLane& lane : lanes)
    for (const Vec2& p : lane.points)
      lane_columns_by_row[static_cast<int>(p.y())].push_back({p.x(), threshold * lane.threshold_scale});
  // Each line's column on each annotated row (once: the bisection is the cost).
  std::vector<std::map<int, double>> columns(lines.size());
  for (std::size_t k = 0; k < lines.size(); ++k)
    for (const auto& [row, unused] : lane_columns_by_row)
      if (const std::optional<double> x = column_in_picture(camera, lines[k], row, width, rules)) columns[k][row] = *x;

  for (std::size_t i = 0; i < lanes.size(); ++i) {
    const AnnotatedLane& lane = lanes[i];
    const double lane_threshold = threshold * lane.threshold_scale;
    // Line k's column on point p's row minus the point's; empty where it has none there.
    const auto offset = [&](std::size_t k, const Vec2& p) -> std::optional<double> {
      const auto it = columns[k].find(static_cast<int>(p.y()));
      if (it == columns[k].end()) return std::nullopt;
      return it->second - p.x();
    };
    const auto within = [&](const std::optional<double>& o) { return o && std::abs(*o) <= lane_threshold; };
    const auto hit = [&](std::size_t k, const Vec2& p) { return within(offset(k, p)); };
    std::size_t best = 0, best_line = lines.size();
    for (std::size_t k = 0; k < lines.size(); ++k) {
      const auto hits = static_cast<std::size_t>(
          std::count_if(lane.points.begin(), lane.points.end(), [&](const Vec2& p) { return hit(k, p); }));
      if (hits > best || best_line == lines.size()) best = hits, best_line = k;
    }
    if (point_hits) {
      LaneHits& h = (*point_hits)[i];
      if (best > 0) h.line = static_cast<int>(best_line);
      for (const Vec2& p : lane.points) {
        const std::optional<double> o = best > 0 ? offset(best_line, p) : std::nullopt;
        h.hit.push_back(within(o));
        h.offset_px.push_back(o);
      }
    }
    const bool found = rules.lane_found(best, lane.points.size());
    score.points += lane.points.size();
    score.hit_points += best;
    score.found += found;
    if (lane.ego) {
      ++score.ego_lanes;
      score.ego_points += lane.points.size();
      score.ego_hit_points += best;
      score.ego_found += found;
    }
  }
  if (line_results) line_results->assign(lines.size(), {});
  for (std::size_t k = 0; k < lines.size(); ++k) {
    if (columns[k].empty()) continue;
    std::size_t on_lane = 0;
    for (const auto& [row, x] : columns[k]) {
      const std::vector<LanePoint>& lane_xs = lane_columns_by_row[row];
      const bool on = std::any_of(lane_xs.begin(), lane_xs.end(),
                                  [&](const LanePoint& c) { return std::abs(c.x - x) <= c.threshold; });
      on_lane += on;
      if (line_results && !on) (*line_results)[k].off_rows.push_back(row);
    }
    ++score.reported;
    const bool false_line = static_cast<double>(on_lane) < rules.true_fraction * static_cast<double>(columns[k].size());
    score.false_lines += false_line;
    if (line_results) {
      (*line_results)[k].points = columns[k].size();
      (*line_results)[k].on_lane = on_lane;
      (*line_results)[k].false_line = false_line;
    }
  }
  return score;
}

LaneEvalScore lane_eval_frame(std::span<const AnnotatedLane> lanes, std::span<const double> rows, int width,
                              const CameraModel& camera, std::span<const RoadLine> lines, const ScoreRules& rules) {
  constexpr double kNone = -100.0;  // lane.py's stand-in for a row without a point (-2)
  const double threshold = ScoreRules::threshold_for_width(rules.threshold_px, width);
  const std::size_t n = rows.size();
  LaneEvalScore s;
  if (lanes.empty() || n == 0) return s;
  if (lines.size() > lanes.size() + 2) return {0.0, 0.0, 1.0};
  // Every line's column on every sampled row, 1-based, kNone outside the picture.
  std::vector<std::vector<double>> predicted(lines.size(), std::vector<double>(n, kNone));
  for (std::size_t k = 0; k < lines.size(); ++k)
    for (std::size_t r = 0; r < n; ++r)
      if (const std::optional<double> x = column_in_picture(camera, lines[k], rows[r], width, rules))
        predicted[k][r] = *x;
  double sum = 0.0, worst = 1.0;
  int matched = 0, missed = 0;
  for (const AnnotatedLane& lane : lanes) {
    std::vector<double> labelled(n, kNone);
    for (const Vec2& p : lane.points)
      for (std::size_t r = 0; r < n; ++r)
        if (std::abs(p.y() - rows[r]) < 0.5) labelled[r] = p.x();
    double best = 0.0;
    for (const std::vector<double>& xs : predicted) {
      std::size_t hits = 0;
      for (std::size_t r = 0; r < n; ++r) hits += std::abs(xs[r] - labelled[r]) < threshold * lane.threshold_scale;
      best = std::max(best, static_cast<double>(hits) / static_cast<double>(n));
    }
    (best < rules.found_fraction ? missed : matched) += 1;
    sum += best;
    worst = std::min(worst, best);
  }
  const std::size_t num_lanes = lanes.size();
  if (num_lanes > 4 && missed > 0) --missed;
  if (num_lanes > 4) sum -= worst;
  const double lanes_counted = std::max(1.0, std::min(4.0, static_cast<double>(num_lanes)));
  s.accuracy = sum / lanes_counted;
  const int num_lines = static_cast<int>(lines.size());
  s.fp = num_lines == 0 ? 0.0 : static_cast<double>(num_lines - matched) / num_lines;
  s.fn = missed / lanes_counted;
  return s;
}

}  // namespace ccdlane::cli
