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
  return out;
}

FrameScore score_frame(std::span<const AnnotatedLane> lanes, int width, const CameraModel& camera,
                       std::span<const RoadLine> lines, const ScoreRules& rules) {
  const double threshold = ScoreRules::threshold_for_width(rules.threshold_px, width);
  FrameScore score;
  score.lanes = static_cast<int>(lanes.size());
  // Every row some lane covers, with that lane's centre: a line's points are sampled there.
  std::map<int, std::vector<double>> lane_columns_by_row;
  for (const AnnotatedLane& lane : lanes)
    for (const Vec2& p : lane.points) lane_columns_by_row[static_cast<int>(p.y())].push_back(p.x());
  // Each line's column on each annotated row (once: the bisection is the cost).
  std::vector<std::map<int, double>> columns(lines.size());
  for (std::size_t k = 0; k < lines.size(); ++k)
    for (const auto& [row, unused] : lane_columns_by_row) {
      const std::optional<double> x = road_line_column_at_row(camera, lines[k], row, rules.near_mm, rules.far_mm);
      if (x && *x >= 0.5 && *x <= width + 0.5) columns[k][row] = *x;
    }

  for (const AnnotatedLane& lane : lanes) {
    std::size_t best = 0;
    for (std::size_t k = 0; k < lines.size(); ++k) {
      std::size_t hits = 0;
      for (const Vec2& p : lane.points) {
        const auto it = columns[k].find(static_cast<int>(p.y()));
        hits += it != columns[k].end() && std::abs(it->second - p.x()) <= threshold;
      }
      best = std::max(best, hits);
    }
    score.points += lane.points.size();
    score.hit_points += best;
    if (!lane.points.empty() &&
        static_cast<double>(best) >= rules.found_fraction * static_cast<double>(lane.points.size()))
      ++score.found;
  }
  for (std::size_t k = 0; k < lines.size(); ++k) {
    if (columns[k].empty()) continue;
    std::size_t on_lane = 0;
    for (const auto& [row, x] : columns[k]) {
      const std::vector<double>& lane_xs = lane_columns_by_row[row];
      on_lane += std::any_of(lane_xs.begin(), lane_xs.end(), [&](double c) { return std::abs(c - x) <= threshold; });
    }
    ++score.reported;
    if (static_cast<double>(on_lane) < rules.true_fraction * static_cast<double>(columns[k].size()))
      ++score.false_lines;
  }
  return score;
}

}  // namespace ccdlane::cli
