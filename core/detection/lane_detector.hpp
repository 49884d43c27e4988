// Lane-mark detection on one frame: plan the rows to scan from the camera model at the
// current pose, run the row filter, drop what cannot be paint on the road, group the
// rest into lane lines (and, where the own lane's lines were found on one side only, look
// for the other along its length in the picture; on a search's second look, the next
// lanes' lines beyond them too) and choose sub-pixel picks for the solver, labelled by
// line.
#pragma once

#include <cmath>

#include <optional>
#include <span>
#include <vector>

#include "base/image_view.hpp"
#include "core/detection/detection_config.hpp"
#include "core/detection/ground_projector.hpp"
#include "core/detection/lane_marks.hpp"
#include "core/detection/line_grouper.hpp"
#include "core/detection/line_in_picture.hpp"
#include "core/detection/mark_scanner.hpp"

namespace ccdlane {

// What detect() looks for along its length in the picture (line_in_picture.hpp), from a
// pose a solve gave: the own lane's line on a side where none was found, and, also, the
// next lane's line beyond each own line that has nothing found beyond it. The second
// costs about a millisecond, which a still's second look can spend and a tracked frame,
// whose whole budget that is, cannot. A tracked frame (own_lane, with the previous frame's
// lines as priors) looks for the own lane's other line only near where the previous frame
// had it, when it had it (kTrackedWindowMm); a second look, whose lines are its first
// solve's, across every lane width.
enum class PictureSearch { own_lane, own_lane_and_beyond };

// Bends this sharp or sharper turn the road's tangent 40 m ahead (max_range_mm) by 5.7
// degrees or more: on them, with the bend confirmed (detect's bend_confirmed), bars are
// judged against the tangent's point at their distance.
inline constexpr double kTangentRadiusMm = 400000.0;
inline bool bends_sharper_than_tangent_radius(double c_per_mm) {
  return std::abs(c_per_mm) * 2.0 * kTangentRadiusMm >= 1.0;
}

class LaneDetector {
 public:
  // Every workspace is sized here for frames of camera.Nu x camera.Nv; detect() never
  // allocates and never throws.
  LaneDetector(const CameraSpec& camera, const DetectionConfig& config);

  // Detects lane lines in `image` (Nu x Nv, mono8 or mono16 with its significant_bits),
  // seen from `pose` (the best current guess: previous frame, gyro, or nominal). `priors`
  // are the previous frame's lines in the same road frame (empty on the first frame or
  // after a loss). `bend_confirmed`: the priors' curvature is a lane's that the previous
  // frame found (not a search's first solve, nor lines a track of clutter carries): bars
  // are then judged against the road's tangent at their distance. The result stays valid
  // until the next call.
  const DetectionResult& detect(const ImageView& image, const CameraPose& pose, std::span<const RoadLine> priors,
                                PictureSearch picture_search = PictureSearch::own_lane, bool bend_confirmed = false);

  // The bars the row filter finds on the rows of the searched range seen from `pose`,
  // without the road-plane, width, orientation and step tests or any grouping (a raised
  // marker's lit cap is narrower than paint, and the widths a guessed pose expects are
  // off): for the vanishing point of a search (vanishing_lines.hpp). Their px, py,
  // widths and contrast are set, nothing else. Valid until the next call.
  std::span<const MarkCandidate> bars(const ImageView& image, const CameraPose& pose);
  // The last scan's contrast threshold on each scan row (a bar's scan_row indexes it) as
  // a share of the configured one: the light of the bar's band of rows, 1 in daylight
  // (contrast_threshold.hpp). Valid until the next scan.
  std::span<const float> row_threshold_shares() const {
    return {row_share_.data(), static_cast<std::size_t>(num_rows_)};
  }

  int max_picks() const { return config_.max_picks; }
  int max_candidates() const { return static_cast<int>(marks_.size()); }

 private:
  // `joints`: rows where markers are looked for are also searched for joints between
  // slabs (detection's grouping uses them; the vanishing point's bars do not).
  void plan_rows(const CameraPose& pose, double curvature_per_mm, bool joints);
  // Plans the rows and runs the row filter over them into marks_; how many it found.
  int scan(const ImageView& image, const CameraPose& pose, double curvature_per_mm, bool joints);
  // Sets c.X, c.Y where c lies on the road; false off the road or the searched range.
  bool on_the_road(MarkCandidate& c) const;
  bool points_to_vanishing_point(const ImageView& image, const MarkCandidate& c) const;
  // Whether candidate c (on the road at c.X, c.Y) is a short blob: bright over no more of
  // the road than a raised marker, and dark all around. If so, sets its dot_top and
  // dot_bottom (the rows it is lit over).
  bool is_dot(const ImageView& image, MarkCandidate& c, float levels_per_grey) const;
  // How many rows a marker at 1-based pixel (px, py), X mm ahead on the road, may span;
  // 0 off the road or where one row spans more of the road than a marker is long.
  int dot_rows_limit(double px, double py, double X) const;
  // The road's width one pixel spans across the row at candidate c (on the road at c.X,
  // c.Y); 0 where the next pixel's ray misses the road.
  double mm_per_px_across(const MarkCandidate& c) const;
  // The same for a marker found as a lit cap beside its shadow (c.shadow_side != 0).
  bool is_shadowed_dot(const ImageView& image, MarkCandidate& c, float levels_per_grey) const;
  // Drops the markers of marks_[0, kept) whose shadow falls against the picture's sun;
  // returns how many are left.
  int keep_one_sun(int kept);
  // Drops the joints of marks_[0, kept) with no piece on a neighbouring scan row along
  // the line to the vanishing point through them (cracks and specks; a joint runs along
  // the road); returns how many are left.
  int keep_linked_joints(int kept);
  // Drops the bars of marks_[0, kept) that stand side by side across the road on their
  // row, a crossing's (kMinCrossingBars); returns how many are left.
  int drop_crossings(int kept);
  // The road's millimetres per pixel across scan row r (one along a row: a flat road,
  // level), from the mark width planned for it.
  double row_mm_per_px(const ScanRow& r) const;
  // Whether bar c is the road between the two dark beads of a sealed crack: a narrow dark
  // valley at each of its edges with road as bright as it beyond (paint stands above the
  // road beyond its edges).
  bool between_beads(const ImageView& image, const MarkCandidate& c) const;
  // Whether candidate c is yellow paint (colour frames only).
  static bool is_yellow(const ImageView& image, const MarkCandidate& c);
  // The picks, evenly spread over each line's marks of its kind, and a joint line's dots
  // beyond its joint's ends (at `pose`, detection's).
  void choose_picks(const CameraPose& pose);
  // Where the lines found all lie on one side of the vehicle, or (a tracked frame) the
  // nearest on either side are two lanes apart or more where the previous frame had the
  // own lane's line between them, the own lane's line on the other side of the nearest
  // looked for along its length in the picture (line_in_picture.hpp), and added to the
  // result's lines with its hits as marks. `kept`: marks_ in use. Returns marks in use.
  // detect() asks for it only when it has lines to go on (its pose is a solve's).
  // `tracked`: lines of the previous frame, near one of which on that side the line is
  // looked for; empty: across every own lane's width.
  int add_line_in_picture(const ImageView& image, const CameraPose& pose, std::span<const RoadLine> tracked, int kept,
                          float levels_per_grey);
  // Beyond each own lane's line with no line found beyond it (and not yellow or solid:
  // the travelled way's edge), the next lane's line looked for the same way, on any road.
  int add_lines_beyond_in_picture(const ImageView& image, const CameraPose& pose, int kept, float levels_per_grey);
  // The share of the scan rows line j's marks (of marks_[0, kept)) span that hold one.
  double scan_row_coverage(int j, int kept) const;
  // The line a lane's width to `side` (+1 left, -1 right) of `beside`, looked for in the
  // picture by `chance`'s rule and, when found, inserted at `index` of the result's lines
  // (those from there on move one up, their marks with them). Returns marks in use.
  // `near_mm`: where the line was last (its offset from `beside`, signed), to look within
  // kTrackedWindowMm of; none: across the own lane's widths. `widest_mm`: no farther from
  // `beside` than this (a line found beyond the one looked for).
  int look_for_line_in_picture(const ImageView& image, const CameraPose& pose, const RoadLine& beside, double side,
                               int index, ChanceRule chance, int kept, float levels_per_grey,
                               std::optional<double> near_mm = std::nullopt,
                               std::optional<double> widest_mm = std::nullopt);
  // How far across the road line j's dots lie from its joint's pieces, on average (mm,
  // + left); 0 with fewer than kMinDotsBesideJoint dots or no joint's pieces.
  double dots_beside_joint_mm(int j) const;
  // How far across the road the middle of line j's double line lies from its own stripe
  // (mm, + left): half the distance to the second stripe beside it; 0 when there is none.
  double double_line_middle_mm(int j) const;

  CameraSpec camera_;
  DetectionConfig config_;
  GroundProjector projector_;
  MarkScanner scanner_;
  LineGrouper grouper_;
  PictureLineSearch picture_line_;
  std::vector<ScanRow> rows_;
  std::vector<float> row_share_;     // row_contrast_ over the configured threshold (bars())
  std::vector<float> row_contrast_;  // per scan row: its band's threshold, or the frame's where lower
  int num_rows_ = 0;
  std::vector<MarkCandidate> marks_;
  std::vector<int> joints_;           // keep_linked_joints' indices into marks_,
  std::vector<std::uint8_t> linked_;  // and whether each is linked
  std::vector<int> row_bars_;         // drop_crossings' bars of one row, by their place across
  std::vector<std::uint8_t> crossing_;  // and whether each mark is a crossing's
  std::vector<Pick> picks_;
  DetectionResult result_;
  float min_contrast_ = 0.0f;       // this frame's (contrast_threshold.hpp), measure levels
  double vp_x_ = 0.0, vp_y_ = 0.0;  // ideal pixel of the road's vanishing point
  bool have_vp_ = false;
  // The priors' mean slope, and their mean curvature where bars are judged against the
  // road's tangent (detect's bend_confirmed, a bend sharper than kTangentRadiusMm), else 0.
  double road_m_ = 0.0, road_c_per_mm_ = 0.0;
};

}  // namespace ccdlane
