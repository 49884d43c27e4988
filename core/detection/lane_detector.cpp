// Lane detector: row plan from the pose, row filter, road-plane and orientation checks,
// grouping, picks. Which of the row filter's candidates are paint, markers or joints is
// lane_detector_marks.cpp's; the lines looked for along their length in the picture
// lane_detector_picture.cpp's.
#include "core/detection/lane_detector.hpp"

#include <algorithm>
#include <cmath>
#include <optional>

#include "core/detection/contrast_threshold.hpp"
#include "core/detection/detection_rules.hpp"
#include "core/detection/paint_measure.hpp"
#include "core/geometry/types.hpp"

namespace ccdlane {

using namespace detection_rules;

namespace {

static_assert(kMaxDetectedLines == kMaxLaneLines, "detection reports at most what the solver takes");

constexpr int kMaxScanRows = 360;              // beyond, rows are subsampled evenly
constexpr int kCandidatesPerPixelRow = 24;     // capacity: marks per scanned row, on average
constexpr double kMinMarkPx = 0.8;             // marks narrower than this are not resolved
// How far to the side rows are scanned, on the road: detection reports the lines nearest
// the vehicle (at most 4, within 2.5 lane widths, 9 m), and grouping gates them a metre
// wide; beyond that, with room for a yaw error of 3 degrees (0.05 per mm ahead), paint
// is never reported and is not looked at.
constexpr double kLateralReachMm = 12000.0;
constexpr double kLateralReachPerMm = 0.05;
// A marker is a dome: in sunlight only its lit side stands out, about half of its
// 10 cm, the other half is its shadow. Bars that narrow are kept as possible dots.
constexpr double kMinDotLitWidthMm = 40.0;
constexpr double kMinShadowedDotPx = 2.5;
constexpr double kRowsPerMarkerForEveryFourth = 4.0;
// Contrast markings' black borders are 75-100 mm wide (3-4 in., some US states on pale
// concrete); a band this wide at least beside each of a bar's edges is one.
constexpr double kMinContrastBorderMm = 50.0;
// A line's dots needed to say how far beside its joint they lie: each is placed to a
// pixel or so (10-35 mm at 10-35 m), a few of them to a centimetre.
constexpr int kMinDotsBesideJoint = 3;
// A double line is two stripes of paint side by side (a no-passing line, a carpool
// lane's edge): 10-15 cm each with 10-30 cm between them, their middles this far apart,
// with room for an unsettled height's scale. Its second stripe is paint as the first is:
// as wide, give or take this factor, and as bright, give or take twice; and it runs
// beside it along most of it, at one distance (within this share of it, or the spread).
constexpr double kMinStripeGapMm = 150.0;
constexpr double kMaxStripeGapMm = 600.0;
constexpr double kStripeWidthRatio = 1.6;
constexpr double kStripeContrastRatio = 2.0;
constexpr double kStripeGapShare = 0.2;
constexpr double kStripeGapSpreadMm = 60.0;
constexpr int kMinStripePairs = 8;

}  // namespace

LaneDetector::LaneDetector(const CameraSpec& camera, const DetectionConfig& config)
    : camera_(camera),
      config_(config),
      scanner_(camera.Nu),
      grouper_(static_cast<int>(std::min(camera.Nv, kMaxScanRows)) * kCandidatesPerPixelRow),
      picture_line_(camera),
      rows_(static_cast<std::size_t>(camera.Nv)),
      row_share_(static_cast<std::size_t>(camera.Nv)),
      row_contrast_(static_cast<std::size_t>(camera.Nv)),
      marks_(static_cast<std::size_t>(std::min(camera.Nv, kMaxScanRows)) * kCandidatesPerPixelRow),
      joints_(marks_.size()),
      linked_(marks_.size()),
      row_bars_(marks_.size()),
      crossing_(marks_.size()),
      picks_(static_cast<std::size_t>(config.max_picks)) {}

void LaneDetector::plan_rows(const CameraPose& pose, double curvature_per_mm, bool joints) {
  projector_.set(camera_, pose);
  const CameraModel model(camera_, pose);
  num_rows_ = 0;
  const double col = camera_.cx;
  const int first = std::max(1, config_.roi_top_px), end = camera_.Nv - 1 - config_.hood_px;
  for (int y = first; y < end; ++y) {
    double X = 0, Y = 0, X2 = 0, Y2 = 0;
    if (!projector_.ground(col, y + 1.0, X, Y) || X < config_.min_range_mm || X > config_.max_range_mm) continue;
    if (!projector_.ground(col + 1.0, y + 1.0, X2, Y2)) continue;
    const double mm_per_px = Vec2(X2 - X, Y2 - Y).norm();
    const double mark_px = config_.mark_width_mm / mm_per_px;
    const double min_px = config_.min_mark_width_mm / mm_per_px, max_px = config_.max_mark_width_mm / mm_per_px;
    if (mark_px < kMinMarkPx) continue;
    // Near rows are dense on the road and their marks wide: every second or third one
    // says as much as all of them, at a fraction of the time; every fourth where a raised
    // marker spans four rows or more (each is still crossed by one).
    double X_below = 0.0, Y_below = 0.0;
    const bool below = projector_.ground(col, y + 2.0, X_below, Y_below);
    const bool marker_rows = below && X > X_below && kDotDiameterMm >= kRowsPerMarkerForEveryFourth * (X - X_below);
    const int thin = mark_px >= 12.0 ? (marker_rows ? 4 : 3) : mark_px >= 6.0 ? 2 : 1;
    if (y % thin != 0) continue;
    ScanRow& r = rows_[static_cast<std::size_t>(num_rows_++)];
    r.y = y;
    r.mark_px = static_cast<float>(mark_px);
    r.half_width = std::clamp(static_cast<int>(std::lround(mark_px / 2)), 1, 8);
    // Paint of the accepted widths, with room for blur and a dash's end (narrower) and for
    // the widening towards the picture's edges and one pixel of blur (wider); beyond
    // that, bars are not paint on the road: a barrier's foot seen from a few metres, a
    // kerb's top, text, arrows, patches, cars.
    r.min_width_px = static_cast<float>(std::max(0.8, 0.5 * min_px - 1.0));
    r.max_width_px = static_cast<float>(1.15 * max_px + 2.0);
    r.min_dot_width_px = static_cast<float>(std::max(1.0, kMinDotLitWidthMm / mm_per_px - 1.0));
    // Markers lit from one side, where they are told from paint at all (is_dot: a row
    // spanning more of the road than a marker is long makes a dash a few rows tall too).
    const double dot_px = kDotDiameterMm / mm_per_px;
    const bool dots_told = below && dot_rows_for(std::max(1.0, X - X_below)) > 0;
    r.dot_px = dots_told && dot_px >= kMinShadowedDotPx ? static_cast<float>(dot_px) : 0.0f;
    // Joints, where markers are looked for: a joint only ever joins a row of them.
    r.max_joint_px = joints && r.dot_px > 0.0f ? static_cast<float>(max_joint_px(mm_per_px)) : 0.0f;
    r.min_border_px = static_cast<float>(std::max(1.0, kMinContrastBorderMm / mm_per_px - 1.0));
    // The columns of the road within reach on this row (its centre's distance), where the
    // road bends as the previous frame's lines did. Outside the picture's side edges the
    // projection may not exist: then the row's end.
    const double reach = kLateralReachMm + kLateralReachPerMm * X, bend = curvature_per_mm * X * X;
    const auto left = model.pixel_from_point(Vec3(X, bend + reach, 0.0));
    const auto right = model.pixel_from_point(Vec3(X, bend - reach, 0.0));
    const int margin = 2 * (r.half_width + static_cast<int>(std::ceil(r.max_width_px)));  // the bar's flanks
    r.x_begin = left && left->x() > 0.0 ? std::max(0, static_cast<int>(left->x()) - margin) : 0;
    r.x_end =
        right && right->x() < camera_.Nu ? std::min(camera_.Nu, static_cast<int>(right->x()) + margin) : camera_.Nu;
  }
  if (num_rows_ > kMaxScanRows) {  // keep an even spread
    const int n = num_rows_;
    for (int k = 0; k < kMaxScanRows; ++k)
      rows_[static_cast<std::size_t>(k)] = rows_[static_cast<std::size_t>(static_cast<long>(k) * n / kMaxScanRows)];
    num_rows_ = kMaxScanRows;
  }
}

double LaneDetector::dots_beside_joint_mm(int j) const {
  const RoadLine& fit = result_.lines[static_cast<std::size_t>(j)].fit;
  double dots = 0.0, joint = 0.0;
  int num_dots = 0, num_joint = 0;
  for (const MarkCandidate& m : result_.marks) {
    if (m.line != j) continue;
    const double across = m.Y - fit.y_at(m.X);
    if (m.joint) {
      joint += across;
      ++num_joint;
    } else if (m.dot) {
      dots += across;
      ++num_dots;
    }
  }
  if (num_dots < kMinDotsBesideJoint || num_joint == 0) return 0.0;
  return dots / num_dots - joint / num_joint;
}

double LaneDetector::double_line_middle_mm(int j) const {
  // Rows where the line has a bar of paint and another bar of paint that joined no line
  // lies beside it, as wide and as bright, a double line's gap away. Marks come in scan
  // row order: a row's bars are neighbours.
  const std::span<const MarkCandidate> marks = result_.marks;
  const auto paint = [](const MarkCandidate& m) { return !m.dot && !m.joint && !m.for_lines_beyond; };
  const auto stripes = [&](const MarkCandidate& own, const MarkCandidate& other) {  // on one scan row
    const double gap = other.Y - own.Y;
    return other.line < 0 && paint(other) && std::abs(gap) >= kMinStripeGapMm && std::abs(gap) <= kMaxStripeGapMm &&
           other.width_px() <= kStripeWidthRatio * own.width_px() &&
           own.width_px() <= kStripeWidthRatio * other.width_px() &&
           other.contrast <= kStripeContrastRatio * own.contrast &&
           own.contrast <= kStripeContrastRatio * other.contrast;
  };
  // Every such pair's gap, to each side; then, on the side with more, those at one gap
  // about their mean (a second stripe is at one distance, clutter at any).
  int own_bars = 0;
  const auto for_each_pair = [&](const auto& take) {
    for (std::size_t i = 0; i < marks.size(); ++i) {
      const MarkCandidate& own = marks[i];
      if (own.line != j || !paint(own)) continue;
      for (std::size_t k = i; k-- > 0 && marks[k].scan_row == own.scan_row;)
        if (stripes(own, marks[k])) take(marks[k].Y - own.Y);
      for (std::size_t k = i + 1; k < marks.size() && marks[k].scan_row == own.scan_row; ++k)
        if (stripes(own, marks[k])) take(marks[k].Y - own.Y);
    }
  };
  for (const MarkCandidate& m : marks) own_bars += m.line == j && paint(m);
  double sum[2] = {0.0, 0.0};
  int count[2] = {0, 0};
  for_each_pair([&](double gap) {
    sum[gap > 0.0] += gap;
    ++count[gap > 0.0];
  });
  const int side = count[1] > count[0] ? 1 : 0;
  if (count[side] < kMinStripePairs) return 0.0;
  const double mean = sum[side] / count[side];
  const double spread = std::max(kStripeGapSpreadMm, kStripeGapShare * std::abs(mean));
  double at_one_gap = 0.0;
  int pairs = 0;
  for_each_pair([&](double gap) {
    if (std::abs(gap - mean) > spread) return;
    at_one_gap += gap;
    ++pairs;
  });
  if (pairs < kMinStripePairs || 2 * pairs < own_bars) return 0.0;
  return 0.5 * at_one_gap / pairs;
}

void LaneDetector::choose_picks(const CameraPose& pose) {
  const CameraModel model(camera_, pose);
  const int n = result_.num_lines;
  int count = 0;
  const int per_line = n > 0 ? config_.max_picks / n : 0;
  const int num_marks = static_cast<int>(result_.marks.size());
  for (int j = 0; j < n; ++j) {
    DetectedLine& line = result_.lines[static_cast<std::size_t>(j)];
    line.first_pick = count;
    // A line of paint hands on its paint only: the blobs grouped with it (a dash's end,
    // a dot beside it) are not where its edges say the line is. A row of dots (its
    // majority kind, as the grouping found) hands on its dots; a row of dots set beside a
    // joint, the joint moved across to where its dots are: the joint is continuous and
    // sharp, so it gives the line's direction and shape better than a few scattered
    // dots; the dots, 5-15 cm beside it, are the marking (and where benchmarks label
    // the line). Left on the joint, the line missed the labels by 20-45 px at 3-6 m. A
    // double line's stripe hands on its bars moved to the double line's middle.
    const bool dots = line.dots;
    const bool joint = line.joints > 0;
    const auto usable_mark = [j, dots, joint](const MarkCandidate& m) {
      return m.line == j && (joint ? m.joint : m.dot == dots && !m.joint);
    };
    const double across = joint ? dots_beside_joint_mm(j) : dots ? 0.0 : double_line_middle_mm(j);
    const auto pick = [&](const MarkCandidate& m) {
      if (across != 0.0)
        if (const std::optional<Vec2> p = model.pixel_from_point(Vec3(m.X, m.Y + across, 0.0)))
          return Pick{j, p->x(), p->y()};
      return Pick{j, m.px(), m.py};
    };
    int usable = 0;
    double joint_near = 1e300, joint_far = -1e300;
    for (const MarkCandidate& m : result_.marks) {
      usable += usable_mark(m);
      if (joint && m.line == j && m.joint) joint_near = std::min(joint_near, m.X), joint_far = std::max(joint_far, m.X);
    }
    // Where the joint does not reach but the line does through its dots (the grouping's
    // reach_through_dots: past a worn, filled or hidden piece of the joint), the dots are
    // the line's only evidence: their own picks, first.
    const auto beyond_the_joint = [&](const MarkCandidate& m) {
      return m.line == j && m.dot && !m.joint && (m.X < joint_near || m.X > joint_far) && m.X >= line.near_mm &&
             m.X <= line.far_mm;
    };
    int beyond = 0;
    if (joint)  // a paint line (most of them) needs no pass for it
      for (const MarkCandidate& m : result_.marks)
        if (beyond < per_line / 4 && beyond_the_joint(m))
          picks_[static_cast<std::size_t>(count + beyond++)] = Pick{j, m.px(), m.py};
    count += beyond;
    // Evenly spread over the line's marks (they come in row order, far to near).
    const int take = std::min(usable, per_line - beyond);
    int seen = 0, next = 0;
    for (int i = 0; i < num_marks && next < take; ++i) {
      const MarkCandidate& m = result_.marks[static_cast<std::size_t>(i)];
      if (!usable_mark(m)) continue;
      if (seen++ == static_cast<int>(static_cast<long>(2 * next + 1) * usable / (2 * take))) {
        picks_[static_cast<std::size_t>(count++)] = pick(m);
        ++next;
      }
    }
    line.num_picks = count - line.first_pick;
  }
  result_.picks = std::span<const Pick>(picks_.data(), static_cast<std::size_t>(count));
}

int LaneDetector::scan(const ImageView& image, const CameraPose& pose, double curvature_per_mm, bool joints) {
  plan_rows(pose, curvature_per_mm, joints);
  const float scale = paint_measure_levels_per_grey(image);
  min_contrast_ = contrast_thresholds(image, {rows_.data(), static_cast<std::size_t>(num_rows_)},
                                      static_cast<float>(config_.min_contrast), scale, row_contrast_);
  const int capacity = static_cast<int>(marks_.size());
  int count = 0;
  scanner_.clear_edges();
  for (int r = 0; r < num_rows_ && count < capacity; ++r)
    count = scanner_.scan(image, rows_[static_cast<std::size_t>(r)], r, row_contrast_[static_cast<std::size_t>(r)],
                          1.0f / scale, marks_.data(), count, capacity);
  // The step test as far out as the picture's blur needs (a blurred edge's ramp is no step).
  if (const int offset = scanner_.step_window_offset(); offset > 0)
    for (int i = 0; i < count; ++i) {
      MarkCandidate& c = marks_[static_cast<std::size_t>(i)];
      c.step_beside = (c.step_beside_at >> offset) & 1;
    }
  return count;
}

bool LaneDetector::on_the_road(MarkCandidate& c) const {
  double X = 0, Y = 0;
  if (!projector_.ground(c.px(), c.py, X, Y) || X < 0.8 * config_.min_range_mm || X > 1.25 * config_.max_range_mm)
    return false;
  c.X = X;
  c.Y = Y;
  return true;
}

std::span<const MarkCandidate> LaneDetector::bars(const ImageView& image, const CameraPose& pose) {
  if (image.empty() || image.width != camera_.Nu || image.height != camera_.Nv) return {};
  // No joints: the vanishing point is found from the lines of paint and markers.
  const int count = scan(image, pose, 0.0, false);
  const float configured = static_cast<float>(config_.min_contrast) * paint_measure_levels_per_grey(image);
  for (int r = 0; r < num_rows_; ++r)
    row_share_[static_cast<std::size_t>(r)] = row_contrast_[static_cast<std::size_t>(r)] / configured;
  return {marks_.data(), static_cast<std::size_t>(count)};
}

const DetectionResult& LaneDetector::detect(const ImageView& image, const CameraPose& pose,
                                            std::span<const RoadLine> priors, PictureSearch picture_search,
                                            bool bend_confirmed) {
  result_ = DetectionResult{};
  if (image.empty() || image.width != camera_.Nu || image.height != camera_.Nv) return result_;
  double mean_m = 0.0, mean_c = 0.0;
  for (const RoadLine& p : priors) {
    mean_m += p.m / static_cast<double>(priors.size());
    mean_c += p.c_per_mm / static_cast<double>(priors.size());
  }
  const int count = scan(image, pose, mean_c, true);
  have_vp_ = projector_.vanishing_point(mean_m, vp_x_, vp_y_);
  road_m_ = mean_m;
  // The tangent's point (points_to_vanishing_point) from a curvature the previous frame's
  // lane had; a search's first solve, which a look again starts from, has its curvature
  // from a few marks, and lines tracked without a lane may be clutter's.
  // Only a bend sharper than kTangentRadiusMm: on a gentler one the straight road's point
  // is within a few degrees of every tangent's in the searched range, and the tangent of
  // a slightly wrong curvature (a word taken for a line) lets other bars in.
  road_c_per_mm_ = bend_confirmed && bends_sharper_than_tangent_radius(mean_c) ? mean_c : 0.0;
  const float scale = paint_measure_levels_per_grey(image);
  result_.counters.scan_rows = num_rows_;
  result_.counters.candidates = count;

  // What cannot be paint on the road: off the road plane or the searched range, or a bar
  // that does not run towards the vanishing point (shadow edges, car parts, seams).
  int kept = 0;
  for (int i = 0; i < count; ++i) {
    MarkCandidate c = marks_[static_cast<std::size_t>(i)];
    if (!on_the_road(c)) {
      ++result_.counters.off_road;
      continue;
    }
    if (c.joint) {  // its direction is keep_linked_joints' to judge
      marks_[static_cast<std::size_t>(kept++)] = c;
      continue;
    }
    c.dot = c.shadow_side != 0 ? is_shadowed_dot(image, c, scale) : is_dot(image, c, scale);
    if (c.narrow && !c.dot) {
      ++result_.counters.narrow;
      continue;
    }
    c.yellow = !c.dot && is_yellow(image, c);
    // A step beside a bar biases its edges, unless the bar is yellow paint: on pale
    // concrete the step beside yellow paint is its own colour bled into its sides (colour
    // is sampled at half the resolution and blurred again by video codecs), the same on
    // either side, and the bar's centre stays where the paint is. Barrier feet, kerbs,
    // seams and slab edges, whose steps do bias, are grey.
    // Such a bar is held for a line beyond the road's others (lane_marks.hpp,
    // for_lines_beyond); a marker's cap beside its shadow that is no marker is no line's.
    if (c.step_beside && !c.dot && !c.yellow) {
      ++result_.counters.step_beside;
      if (c.shadow_side != 0) continue;
      c.for_lines_beyond = true;
    }
    if (!c.dot && !points_to_vanishing_point(image, c)) {
      ++result_.counters.wrong_orientation;
      continue;
    }
    if (!c.dot && !c.yellow && between_beads(image, c)) {
      ++result_.counters.between_beads;
      continue;
    }
    result_.counters.dots += c.dot;
    result_.counters.yellow += c.yellow;
    marks_[static_cast<std::size_t>(kept++)] = c;
  }
  kept = keep_one_sun(kept);
  kept = keep_linked_joints(kept);
  kept = drop_crossings(kept);
  const std::span<MarkCandidate> marks(marks_.data(), static_cast<std::size_t>(kept));
  GroupingParams params;
  params.min_marks = config_.min_marks;
  params.max_lines = config_.max_lines;
  params.mm_per_px_per_mm = camera_.pitch_u() / pose.f_mm;
  params.height_mm = pose.H_mm;
  // Without lines to go on, the pose is a search's guess (detection_config.hpp).
  if (priors.empty()) params.max_pitch_error_rad = deg_to_rad(kSearchPitchErrorDeg);
  params.tracked_priors = !priors.empty() && picture_search == PictureSearch::own_lane;
  result_.num_lines = grouper_.group(marks, priors, params, result_.lines);
  // The held bars no line beyond took are nothing of the road's.
  int grouped = 0;
  for (const MarkCandidate& m : marks)
    if (!m.for_lines_beyond || m.line >= 0) marks_[static_cast<std::size_t>(grouped++)] = m;
  // The own lane's other line in the picture only from a pose a solve gave (a search's
  // look again, or the previous frame's): from a guessed pose, a lane's width across says
  // little of where in the picture that line runs.
  if (!priors.empty()) {
    const bool tracked = picture_search == PictureSearch::own_lane;
    grouped = add_line_in_picture(image, pose, tracked ? priors : std::span<const RoadLine>{}, grouped, scale);
    if (picture_search == PictureSearch::own_lane_and_beyond)
      grouped = add_lines_beyond_in_picture(image, pose, grouped, scale);
  }
  result_.marks = std::span<const MarkCandidate>(marks_.data(), static_cast<std::size_t>(grouped));
  for (const MarkCandidate& m : result_.marks) result_.counters.grouped += m.line >= 0;
  choose_picks(pose);
  return result_;
}

}  // namespace ccdlane
