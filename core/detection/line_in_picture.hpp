// The own lane's other line, looked for along its whole length in the picture.
//
// The row filter keeps a bar only when it is told as paint or as a raised marker on its
// own, and grouping needs several such marks. A line of Botts' dots three or four metres
// apart, half of them lost in a car's shadow, or a line whose markers are seen 20-40 m
// ahead as specks a few pixels wide, leaves too few. Where one of the own lane's lines is
// found and the other is not, the pose and the found line say where the other runs in the
// picture to within the lane's width: a one-parameter family of lines, each through the
// road's vanishing point. Along each, every row read either shows a bright bar between
// two darker sides or not; the specks of concrete and asphalt are spread over every
// candidate alike, a line's marks pile up on one. Read so, a line stands out from a few
// dots where no single one of them would (the classic column histogram of a bird's-eye
// view, done in the picture without warping it).
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "base/image_view.hpp"
#include "core/detection/ground_projector.hpp"
#include "core/geometry/camera_model.hpp"
#include "core/geometry/road_line.hpp"

namespace ccdlane {

// One row's place on a candidate line: where a bar stood out on it.
struct PictureLineHit {
  double px = 0, py = 0;  // 1-based observed pixel: the bar's centre
  double half_width_px = 1;
  double contrast = 0;  // measure levels above the brighter side
  double X = 0, Y = 0;  // on the road at the pose, mm
  int row = 0;          // index of the row read (far to near)
};

struct PictureLine {
  bool found = false;
  double offset_mm = 0;  // of the line found, from the line it was looked for beside (+ left)
  int hits = 0;          // rows along it where a bar stands out
  int groups = 0;        // separate places along the road they lie in (kGroupGapMm apart)
  int dashes = 0;        // of them, places whose hits run over kMinDashMm of road or more
  // Separate pieces in the picture: runs of hits on consecutive rows read. A car's back,
  // upright, spans rows that meet the road over tens of metres: many places on the road,
  // one piece in the picture.
  int pieces = 0;
  double span_mm = 0;                     // the road they spread over
  double baseline = 0;                    // the hits a candidate has by chance: the median candidate's
  double spread = 0;                      // and chance's standard deviation about it
  std::span<const PictureLineHit> marks;  // the hits of the line found
};

// Whether a line may be taken where chance alone puts hits on most candidates. The own
// lane's other line is looked for on a clean road only: a lane that one line of bars and
// one from the picture would make is no lane where the picture is bars everywhere (bright
// noise made such lanes). Beyond a lane found, a line is there on most roads (freeways
// have several lanes), and on a textured one (concrete's specks and seams) it needs only
// to stand out from the texture's hits by kMinSigmas of their spread.
enum class ChanceRule { clean_road, any_road };

class PictureLineSearch {
 public:
  // Sized for frames of `camera` (Nu x Nv); find() never allocates.
  explicit PictureLineSearch(const CameraSpec& camera);

  // Looks for a line parallel to `beside` (its slope and curvature), at lateral offsets
  // from_mm..to_mm from it (signed: + left; from_mm < to_mm), over the road near_mm to
  // far_mm ahead as seen from `pose`, for paint `mark_width_mm` wide standing
  // `min_contrast` measure levels above both its sides.
  // `taken`, when given, narrows where the line may be taken (a tracked frame's window
  // about where the previous frame had it) without narrowing where chance is measured:
  // every offset from_mm..to_mm still counts for chance. Measured inside a window a
  // lane's line fills, chance is the line's own hits (its bars are read by the
  // candidates either side of it), and a dashed line of paint was refused there as a
  // textured road.
  struct Window {
    double from_mm = 0.0, to_mm = 0.0;
  };
  const PictureLine& find(const ImageView& image, const CameraPose& pose, const RoadLine& beside, double from_mm,
                          double to_mm, double near_mm, double far_mm, double mark_width_mm, double min_contrast,
                          ChanceRule chance = ChanceRule::clean_road, std::optional<Window> taken = std::nullopt);

  static constexpr double kOffsetStepMm = 40.0;
  // The rows read: each marker this long on the road (a Botts' dot) is crossed by two of
  // them at least, or by one where it spans less than two rows. (Detection's scan rows
  // are thinned for paint and may pass between a dot's.)
  static constexpr double kMarkerLengthMm = 100.0;
  static constexpr int kMaxOffsets = 80;
  static constexpr int kAnchorStep = 4;  // candidates projected exactly, the rest interpolated
  // Hits this far apart along the road are separate marks (a dot's rows, a dash's): half
  // the closest spacing of a line's markers (Caltrans' Botts' dots, 1.2 m) as a pose whose
  // height is 25 % off measures it (0.9 m). A metre merged such dots into one place when
  // the pose shrank the road (a still's first solve, a search's guessed height), and a
  // row of them 4-12 m ahead was refused for being in too few places. A patch's hits on
  // alternate rows near the camera (rows there 50-100 mm apart) are still one place.
  static constexpr double kGroupGapMm = 500.0;
  // What a line needs: hits in this many separate places over this much road, and more
  // hits than chance gives a candidate by this many of chance's standard deviations (at
  // least a Poisson count's, the square root of the count plus one).
  static constexpr int kMinGroups = 4;
  // A place whose hits run over this much road is a dash seen along its length (a dash is
  // 1.5-6 m long; a raised marker's hits lie within 0.3 m, and markers 0.9 m apart or more
  // are separate places). Beyond a lane found (ChanceRule::any_road), this many of them
  // make a line with fewer places: a dashed line seen over two dashes, 3 m long and 9 m
  // apart, between a car and the picture's edge, is two or three places (TuSimple still
  // 34's right next line, 31 hits over 11 m against a median candidate's 0). It still
  // needs kMinPieces: two unbroken runs could be the side skirts of two trucks.
  static constexpr double kMinDashMm = 1000.0;
  static constexpr int kMinDashesBeyond = 2;
  static constexpr int kMinPieces = 4;
  static constexpr double kMinSpanMm = 8000.0;
  static constexpr int kMinHits = 6;
  static constexpr double kMinSigmas = 5.0;
  static constexpr double kMadToSigma = 1.4826;  // a normal spread's sigma over its MAD
  // ChanceRule::clean_road: where chance alone puts more hits than this on the median
  // candidate (a mottled, textured or noisy picture, bars everywhere), a few more on one
  // say nothing of a line.
  static constexpr int kMaxChanceHits = 2;

 private:
  // The bar response of columns [x0, x1) of 0-based row y into ridge_ (x0-based).
  void ridge_row(const ImageView& image, int y, int x0, int x1, int half);

  // The rows read at the pose: where, and the width paint spans on each.
  void plan_rows(const CameraPose& pose, double near_mm, double far_mm, double mark_width_mm);
  struct Row {
    int y = 0;       // 0-based
    double X = 0.0;  // road distance at the principal column, mm
    int half = 1;    // paint's half width, pixels
  };

  CameraSpec camera_;
  std::vector<Row> rows_;
  int num_rows_ = 0;
  std::vector<std::uint16_t> measure_;
  std::vector<std::int32_t> prefix_;
  std::vector<float> ridge_;
  // Per offset, per row read: the best bar the candidate passes on it (contrast 0: none).
  struct Cell {
    std::int16_t x = 0, y = 0, half = 0;  // 0-based pixel, the bar's half width
    float contrast = 0.0f;
  };
  std::vector<Cell> cells_;
  std::vector<Vec2> place_;  // per offset: its pixel on the row being read
  std::vector<int> counts_;
  std::vector<PictureLineHit> found_;
  PictureLine result_;
};

}  // namespace ccdlane
