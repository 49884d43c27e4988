// The own lane's other line along its length in the picture (line_in_picture.hpp).
#include "core/detection/line_in_picture.hpp"

#include <algorithm>
#include <cmath>
#include <optional>

#include "core/detection/paint_measure.hpp"

namespace ccdlane {

PictureLineSearch::PictureLineSearch(const CameraSpec& camera)
    : camera_(camera),
      rows_(static_cast<std::size_t>(camera.Nv)),
      measure_(static_cast<std::size_t>(camera.Nu)),
      prefix_(static_cast<std::size_t>(camera.Nu) + 1),
      ridge_(static_cast<std::size_t>(camera.Nu)),
      cells_(static_cast<std::size_t>(kMaxOffsets) * static_cast<std::size_t>(camera.Nv)),
      place_(static_cast<std::size_t>(kMaxOffsets)),
      counts_(static_cast<std::size_t>(kMaxOffsets)),
      found_(static_cast<std::size_t>(camera.Nv)) {}

void PictureLineSearch::plan_rows(const CameraPose& pose, double near_mm, double far_mm, double mark_width_mm) {
  const GroundProjector projector(camera_, pose);
  num_rows_ = 0;
  for (int y = 0; y < camera_.Nv; ++y) {
    double X = 0.0, Y = 0.0, X_below = 0.0, Y_below = 0.0, X_right = 0.0, Y_right = 0.0;
    if (!projector.ground(camera_.cx, y + 1.0, X, Y) || X < near_mm || X > far_mm) continue;
    if (!projector.ground(camera_.cx, y + 2.0, X_below, Y_below) || !(X > X_below)) continue;
    if (!projector.ground(camera_.cx + 1.0, y + 1.0, X_right, Y_right)) continue;
    const int step = std::max(1, static_cast<int>(kMarkerLengthMm / (X - X_below) / 2.0));
    if (y % step != 0) continue;
    const double mark_px = mark_width_mm / std::hypot(X_right - X, Y_right - Y);
    rows_[static_cast<std::size_t>(num_rows_++)] =
        Row{y, X, std::clamp(static_cast<int>(std::lround(mark_px / 2.0)), 1, 12)};
  }
}

void PictureLineSearch::ridge_row(const ImageView& image, int y, int x0, int x1, int half) {
  // A bar `half` pixels either side of its centre between two darker sides: the middle
  // third of it against the brighter of the two sides beyond it (as wide as it, a pixel
  // off its edge). A step (a shadow's border, a kerb, the edge of a shoulder) is bright
  // on one side only and gives nothing; a wide patch gives nothing at its middle.
  const int core = std::max(0, half / 3), gap = half + 1, side = std::max(2, half);
  const int a = std::max(0, x0 - gap - side), b = std::min(image.width, x1 + gap + side + 1);
  paint_measure_row(image, y, a, b, measure_.data());
  prefix_[static_cast<std::size_t>(a)] = 0;
  for (int x = a; x < b; ++x)
    prefix_[static_cast<std::size_t>(x) + 1] =
        prefix_[static_cast<std::size_t>(x)] + measure_[static_cast<std::size_t>(x)];
  const auto mean = [&](int from, int to) {  // [from, to], clipped; NaN when empty
    from = std::max(from, a), to = std::min(to, b - 1);
    if (to < from) return std::nan("");
    return static_cast<double>(prefix_[static_cast<std::size_t>(to) + 1] - prefix_[static_cast<std::size_t>(from)]) /
           (to - from + 1);
  };
  const auto clipped = [&](int x) {
    const double centre = mean(x - core, x + core);
    const double left = mean(x - gap - side + 1, x - gap), right = mean(x + gap, x + gap + side - 1);
    const double r = centre - std::max(left, right);
    ridge_[static_cast<std::size_t>(x)] = std::isfinite(r) ? static_cast<float>(r) : 0.0f;
  };
  // Where every window lies inside [a, b) (all but a picture's edge columns), the sums
  // need no clipping: integer differences and two multiplications a column.
  const int inner_begin = std::clamp(a + gap + side - 1, x0, x1),
            inner_end = std::clamp(b - gap - side + 1, inner_begin, x1);
  const std::int32_t* const P = prefix_.data();
  const float per_core = 1.0f / static_cast<float>(2 * core + 1), per_side = 1.0f / static_cast<float>(side);
  for (int x = x0; x < inner_begin; ++x) clipped(x);
  for (int x = inner_begin; x < inner_end; ++x) {
    const std::int32_t centre = P[x + core + 1] - P[x - core];
    const std::int32_t left = P[x - gap + 1] - P[x - gap - side + 1], right = P[x + gap + side] - P[x + gap];
    ridge_[static_cast<std::size_t>(x)] =
        static_cast<float>(centre) * per_core - static_cast<float>(std::max(left, right)) * per_side;
  }
  for (int x = inner_end; x < x1; ++x) clipped(x);
}

const PictureLine& PictureLineSearch::find(const ImageView& image, const CameraPose& pose, const RoadLine& beside,
                                           double from_mm, double to_mm, double near_mm, double far_mm,
                                           double mark_width_mm, double min_contrast, ChanceRule chance,
                                           std::optional<Window> taken) {
  result_ = PictureLine{};
  const int offsets = std::clamp(static_cast<int>((to_mm - from_mm) / kOffsetStepMm) + 1, 0, kMaxOffsets);
  if (offsets < 3 || image.width != camera_.Nu || image.height != camera_.Nv) return result_;
  plan_rows(pose, near_mm, far_mm, mark_width_mm);
  const int num_rows = num_rows_;
  const CameraModel model(camera_, pose);
  const GroundProjector projector(camera_, pose);
  std::fill(counts_.begin(), counts_.begin() + offsets, 0);
  const auto cell_at = [this](int k, int i) -> Cell& {
    return cells_[static_cast<std::size_t>(k) * static_cast<std::size_t>(camera_.Nv) + static_cast<std::size_t>(i)];
  };
  for (int i = 0; i < num_rows; ++i) {
    const double X = rows_[static_cast<std::size_t>(i)].X;
    const int half = rows_[static_cast<std::size_t>(i)].half;
    // Each candidate's place on this row: projected every kAnchorStep candidates and in
    // between interpolated (over 160 mm across the road the projection is straight to a
    // hundredth of a pixel).
    // Each anchor is projected once: a step's end is the next step's start.
    const auto anchor = [&](int k) {
      return model.pixel_from_point(Vec3(X, beside.y_at(X) + from_mm + k * kOffsetStepMm, 0.0));
    };
    std::optional<Vec2> a = anchor(0);
    bool seen = a.has_value();
    for (int k = 0; k < offsets && seen; k += kAnchorStep) {
      const int next = std::min(k + kAnchorStep, offsets - 1);
      const std::optional<Vec2> b = next > k ? anchor(next) : a;
      if (!b) {
        seen = false;
        break;
      }
      for (int j = k; j <= next; ++j) {
        const double t = next > k ? static_cast<double>(j - k) / (next - k) : 0.0;
        place_[static_cast<std::size_t>(j)] = *a + t * (*b - *a);
      }
      a = b;
    }
    for (int k = 0; k < offsets; ++k) cell_at(k, i) = Cell{};
    if (!seen) continue;
    // Half a step across on either side of each: every place between two candidates is
    // read. Candidates on one picture row share its bar response, computed once.
    const double step_px = std::abs(place_[static_cast<std::size_t>(offsets - 1)].x() - place_[0].x()) / (offsets - 1);
    const int reach = 1 + static_cast<int>(std::ceil(0.5 * step_px));
    int computed_y = -1, computed_x0 = 0, computed_x1 = 0;
    for (int k = 0; k < offsets; ++k) {
      const Vec2& p = place_[static_cast<std::size_t>(k)];
      const int y = static_cast<int>(std::lround(p.y())) - 1;
      const int x0 = static_cast<int>(std::lround(p.x())) - 1 - reach, x1 = x0 + 2 * reach + 1;
      if (y < 0 || y >= image.height || x0 < 0 || x1 > image.width) continue;
      if (y != computed_y || x0 < computed_x0 || x1 > computed_x1) {
        // This candidate's row and the rest of the candidates' span on it.
        computed_y = y;
        computed_x0 = x0, computed_x1 = x1;
        for (int j = k + 1; j < offsets; ++j) {
          const Vec2& q = place_[static_cast<std::size_t>(j)];
          if (static_cast<int>(std::lround(q.y())) - 1 != y) break;
          const int q0 = static_cast<int>(std::lround(q.x())) - 1 - reach;
          computed_x0 = std::max(0, std::min(computed_x0, q0));
          computed_x1 = std::min(image.width, std::max(computed_x1, q0 + 2 * reach + 1));
        }
        ridge_row(image, y, computed_x0, computed_x1, half);
      }
      // The first strongest response of the candidate's columns, by selects: a branch on
      // which of two neighbouring responses is stronger was mispredicted every few
      // columns (this loop was two fifths of the search).
      int best = x0;
      float r = ridge_[static_cast<std::size_t>(x0)];
      for (int x = x0 + 1; x < x1; ++x) {
        const float v = ridge_[static_cast<std::size_t>(x)];
        const bool stronger = v > r;
        r = stronger ? v : r;
        best = stronger ? x : best;
      }
      if (static_cast<double>(r) < min_contrast) continue;
      cell_at(k, i) =
          Cell{static_cast<std::int16_t>(best), static_cast<std::int16_t>(y), static_cast<std::int16_t>(half), r};
      ++counts_[static_cast<std::size_t>(k)];
    }
  }
  // The candidates the line may be taken from: all, or the window's (its ends may fall on
  // candidates exactly, as a tracked frame's grid puts them: 1e-9 keeps rounding from
  // losing one).
  int first_k = 0, end_k = offsets;
  if (taken) {
    first_k = std::clamp(static_cast<int>(std::ceil((taken->from_mm - from_mm) / kOffsetStepMm - 1e-9)), 0, offsets);
    end_k =
        std::clamp(static_cast<int>(std::floor((taken->to_mm - from_mm) / kOffsetStepMm + 1e-9)) + 1, first_k, offsets);
  }
  if (end_k - first_k < 3) return result_;
  int best_k = first_k;
  for (int k = first_k + 1; k < end_k; ++k)
    if (counts_[static_cast<std::size_t>(k)] > counts_[static_cast<std::size_t>(best_k)]) best_k = k;
  // Chance: the median candidate's hits, and their spread about it (the median absolute
  // deviation, as a standard deviation's estimate): a texture's hits are not spread as
  // independent ones would be (neighbouring candidates share its specks and bars), so
  // chance's spread is measured, not assumed. Both by counting: counts are small
  // integers.
  const auto median_of = [&](auto value) {
    for (int c = 0;; ++c) {
      int at_or_below = 0;
      for (int k = 0; k < offsets; ++k) at_or_below += value(counts_[static_cast<std::size_t>(k)]) <= c;
      if (2 * at_or_below >= offsets) return c;
    }
  };
  const int median = median_of([](int c) { return c; });
  const int mad = median_of([median](int c) { return std::abs(c - median); });
  result_.spread = std::max(std::sqrt(median + 1.0), kMadToSigma * mad);
  result_.baseline = median;
  result_.offset_mm = from_mm + best_k * kOffsetStepMm;
  // The line's hits, far to near, and the separate places they lie in.
  int n = 0, last_row = -2;
  double last_X = 0.0, near = 1e300, far = -1e300;
  double group_from_X = 0.0;  // where the place being read began
  const auto end_group = [&] { result_.dashes += std::abs(last_X - group_from_X) >= kMinDashMm; };
  for (int i = 0; i < num_rows; ++i) {
    const Cell& cell = cell_at(best_k, i);
    double hx = 0.0, hy = 0.0;
    if (!(cell.contrast > 0.0f) || !projector.ground(cell.x + 1.0, cell.y + 1.0, hx, hy)) continue;
    if (n == 0 || std::abs(hx - last_X) > kGroupGapMm) {
      if (n > 0) end_group();
      ++result_.groups;
      group_from_X = hx;
    }
    if (i > last_row + 1) ++result_.pieces;
    last_X = hx;
    last_row = i;
    near = std::min(near, hx), far = std::max(far, hx);
    found_[static_cast<std::size_t>(n++)] = PictureLineHit{
        cell.x + 1.0, cell.y + 1.0, static_cast<double>(cell.half), static_cast<double>(cell.contrast), hx, hy, i};
  }
  if (n > 0) end_group();
  result_.hits = n;
  result_.span_mm = n > 0 ? far - near : 0.0;
  result_.marks = std::span<const PictureLineHit>(found_.data(), static_cast<std::size_t>(n));
  // Above chance, not at either end of the widths it may be taken at (a line nearer or
  // farther than those would peak beyond them), and in enough places along the road: four,
  // or beyond a lane found, two dashes seen along their length (kMinDashesBeyond).
  const bool clean = chance == ChanceRule::any_road || median <= kMaxChanceHits;
  const bool places =
      result_.groups >= kMinGroups || (chance == ChanceRule::any_road && result_.dashes >= kMinDashesBeyond);
  result_.found = n >= kMinHits && clean && n >= median + kMinSigmas * result_.spread && best_k >= first_k + 2 &&
                  best_k < end_k - 2 && places && result_.pieces >= kMinPieces && result_.span_mm >= kMinSpanMm;
  return result_;
}

}  // namespace ccdlane
