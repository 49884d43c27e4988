// Row filter. Along the row: prefix sums, a box derivative at the mark's scale, its
// local extrema as rising/falling edges (parabola-interpolated to sub-pixel), then each
// rising edge paired with the next falling one at a mark-like distance, kept when the
// bar between them is brighter than both of its sides by the minimum contrast.
#include "core/detection/mark_scanner.hpp"

#include <algorithm>
#include <bit>
#include <cassert>
#include <cmath>
#include <cstring>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "core/detection/paint_measure.hpp"
#include "core/detection/pixel_loop_clones.hpp"

namespace ccdlane {
namespace {

// Sub-pixel offset of a peak sampled at -1, 0, 1 with values a, b >= max(a, c), c. A box
// derivative of an edge is a triangle, not a parabola: interpolating with straight
// sides is unbiased where a parabola pulls towards the centre sample.
float peak_offset(std::int32_t a, std::int32_t b, std::int32_t c) {
  const float den = 2.0f * static_cast<float>(b - std::min(a, c));
  if (den <= 0.0f) return 0.0f;
  return std::clamp(static_cast<float>(c - a) / den, -0.5f, 0.5f);
}

// A step beside a bar larger than this fraction of the bar's contrast, within the
// derivative's reach, biases the bar's edges (see scan_row).
constexpr float kStepInReach = 0.25f;
// Contrast markings' black borders are darker than the road beyond them by this many
// minimum contrasts at least (black paint on pale concrete: ten or more); the dark flanks
// of a raised marker's cap or of a joint beside it are not as dark.
constexpr float kBorderDepthContrasts = 3.0f;

// How many pixels from `from` on, going `step`, are darker than `level` (at most `limit`,
// within the row's `width`).
template <typename Pixel>
float dark_run(const Pixel* row, int width, int from, int step, float level, int limit) {
  int n = 0;
  for (int x = from; n < limit && x >= 0 && x < width && static_cast<float>(row[x]) < level; x += step) ++n;
  return static_cast<float>(n);
}

// The row's mean over the h pixels beside one of a bar's edges, and over the h beyond.
struct Flank {
  float near, far;
  float rise() const { return far - near; }
  // The step beside the edge that a bar of level `inside` takes without a biased edge
  // (kStepInReach of its contrast over this side), and whether this one is larger.
  float allowed(float inside) const { return kStepInReach * (inside - near); }
  bool steps(float inside) const { return std::abs(rise()) > allowed(inside); }
};

// Whether a bar with a step beside it is paint between the black borders of contrast
// markings (laid on pale concrete): the row steps back up to the road beyond both
// borders alike, deeply, and the pulls on the bar's two edges are mirror images, within
// what the step test allows the two together, so that the bar's centre stays where the
// paint is. Each border is a dark band at least `min_border_px` wide from the first
// pixel past the bar's edge (`left_from`, `right_from`) outwards, up to `limit`; a joint
// beside a raised marker's cap, or the cap's flanks, are narrower or not as dark.
template <typename Pixel>
bool between_black_borders(const Pixel* row, int width, int left_from, int right_from, const Flank& left,
                           const Flank& right, float inside, float min_contrast, float min_border_px, int limit) {
  const float depth = kBorderDepthContrasts * min_contrast;
  if (!(left.rise() >= depth && right.rise() >= depth)) return false;
  if (std::abs(left.rise() - right.rise()) > left.allowed(inside) + right.allowed(inside)) return false;
  return dark_run(row, width, left_from, -1, 0.5f * (left.near + left.far), limit) >= min_border_px &&
         dark_run(row, width, right_from, +1, 0.5f * (right.near + right.far), limit) >= min_border_px;
}

// A joint's two sides may differ by this fraction of its depth (the slabs beside it
// weathered alike); a shadow's or a patch's border differs by all of it.
constexpr float kJointSideMismatch = 0.5f;

// The mean of a row's pixels a..b (clipped to the row's `width`) from its prefix sums P;
// NaN when nothing is left.
float row_mean(const std::int32_t* P, int width, int a, int b) {
  a = std::max(a, 0);
  b = std::min(b, width - 1);
  if (b < a) return std::nanf("");
  return static_cast<float>(P[b + 1] - P[a]) / static_cast<float>(b - a + 1);
}

// Extremum flags are read this many at a time (one 64-bit word).
constexpr int kFlagWord = 8;

// The box derivative g of half-width h over boundaries lo..hi from the prefix sums P,
// and a flag per boundary lo+1..hi-1: 1 where g peaks at or above the threshold (a
// rising edge), 2 where it dips at or below its negative (a falling one), else 0. Both
// loops are branch-free and vectorised, for the CPU's best target.
CCDLANE_PIXEL_LOOP_CLONES
void box_derivative_extrema(const std::int32_t* __restrict P, int h, int lo, int hi, std::int32_t edge_threshold,
                            std::int32_t* __restrict g, std::uint8_t* __restrict flag) {
  for (int x = lo; x <= hi; ++x) g[x] = P[x + 1 + h] + P[x + 1 - h] - 2 * P[x + 1];
  for (int x = lo + 1; x < hi; ++x) {
    const std::int32_t v = g[x], before = g[x - 1], after = g[x + 1];
    flag[x] = static_cast<std::uint8_t>((v >= edge_threshold) & (v >= before) & (v > after)) |
              static_cast<std::uint8_t>(((v <= -edge_threshold) & (v <= before) & (v < after)) << 1);
  }
}

#if defined(__SSE2__)
// Four 32-bit running sums of v's lanes, each plus `carry` (every lane the total so far);
// the new total in every lane of `carry`.
inline void add_prefix4(__m128i v, __m128i& carry, std::int32_t* __restrict out) {
  v = _mm_add_epi32(v, _mm_slli_si128(v, 4));
  v = _mm_add_epi32(v, _mm_slli_si128(v, 8));
  v = _mm_add_epi32(v, carry);
  _mm_storeu_si128(reinterpret_cast<__m128i*>(out), v);
  carry = _mm_shuffle_epi32(v, _MM_SHUFFLE(3, 3, 3, 3));
}

// Eight pixels as eight 16-bit lanes.
inline __m128i load8(const std::uint16_t* px) { return _mm_loadu_si128(reinterpret_cast<const __m128i*>(px)); }
inline __m128i load8(const std::uint8_t* px) {
  return _mm_unpacklo_epi8(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(px)), _mm_setzero_si128());
}

// Eight pixels at a time, as two vectors of four 32-bit lanes (SSE2, x86-64's baseline);
// returns how many pixels it summed.
template <typename Pixel>
int prefix_sums_vector(const Pixel* __restrict row, int width, std::int32_t* __restrict P) {
  __m128i carry = _mm_setzero_si128();
  const __m128i zero = _mm_setzero_si128();
  int x = 0;
  for (; x + 8 <= width; x += 8) {
    const __m128i px = load8(row + x);
    add_prefix4(_mm_unpacklo_epi16(px, zero), carry, P + x + 1);
    add_prefix4(_mm_unpackhi_epi16(px, zero), carry, P + x + 5);
  }
  return x;
}
#endif

// P[0] = 0, P[x + 1] = row[0] + ... + row[x]. Several pixels at a time: their partial
// sums do not wait for the running total, which is then one addition per four pixels,
// not a chain of one per pixel (the plain loop was two fifths of the row filter's time);
// with SSE2, the partial sums of four are two shifted additions of a vector (this loop
// was still a twelfth of a tracked frame's time).
template <typename Pixel>
void prefix_sums(const Pixel* __restrict row, int width, std::int32_t* __restrict P) {
  P[0] = 0;
  int x = 0;
#if defined(__SSE2__)
  x = prefix_sums_vector(row, width, P);
#endif
  std::int32_t total = P[x];
  for (; x + 4 <= width; x += 4) {
    const std::int32_t a = row[x], ab = a + row[x + 1], abc = ab + row[x + 2], abcd = abc + row[x + 3];
    P[x + 1] = total + a;
    P[x + 2] = total + ab;
    P[x + 3] = total + abc;
    total += abcd;
    P[x + 4] = total;
  }
  for (; x < width; ++x) P[x + 1] = total += row[x];
}

}  // namespace

MarkScanner::MarkScanner(int max_width)
    : measure_(static_cast<std::size_t>(max_width)),
      prefix_(static_cast<std::size_t>(max_width) + 1),
      grad_(static_cast<std::size_t>(max_width)),
      extrema_(static_cast<std::size_t>(max_width) + kFlagWord),
      rising_(static_cast<std::size_t>(max_width)),
      falling_(static_cast<std::size_t>(max_width)),
      edge_ramps_(kMaxEdgeRamps),
      dots_(max_width) {
  assert(max_width < (1 << 15) && "prefix sums of 16-bit pixels are 32-bit");
}

template <typename Pixel>
void MarkScanner::add_edge_ramps(const Pixel* row, int width, int ia, int ib, float left_contrast,
                                 float right_contrast) {
  // The steepest one-pixel rise within two pixels of each edge.
  std::int32_t rise = 0, fall = 0;
  for (int x = std::max(ia - 2, 0); x <= std::min(ia + 2, width - 2); ++x)
    rise = std::max<std::int32_t>(rise, static_cast<std::int32_t>(row[x + 1]) - static_cast<std::int32_t>(row[x]));
  for (int x = std::max(ib - 2, 0); x <= std::min(ib + 2, width - 2); ++x)
    fall = std::max<std::int32_t>(fall, static_cast<std::int32_t>(row[x]) - static_cast<std::int32_t>(row[x + 1]));
  if (rise <= 0 || fall <= 0 || num_edge_ramps_ + 2 > kMaxEdgeRamps) return;
  edge_ramps_[static_cast<std::size_t>(num_edge_ramps_++)] = left_contrast / static_cast<float>(rise);
  edge_ramps_[static_cast<std::size_t>(num_edge_ramps_++)] = right_contrast / static_cast<float>(fall);
}

int MarkScanner::step_window_offset() {
  if (num_edge_ramps_ < kMinRampEdges) return 0;
  const auto begin = edge_ramps_.begin(), end = begin + num_edge_ramps_, middle = begin + num_edge_ramps_ / 2;
  std::nth_element(begin, middle, end);
  const double sigma = static_cast<double>(*middle) / std::sqrt(2.0 * std::acos(-1.0));
  return std::clamp(static_cast<int>(std::lround(kRampPerSigma * (sigma - kSharpEdgeSigmaPx))), 0,
                    kMaxStepWindowOffset);
}

int MarkScanner::scan(const ImageView& image, const ScanRow& r, int scan_row_index, float min_contrast, float to_8bit,
                      MarkCandidate* out, int count, int capacity) {
  const int width = std::min(image.width, static_cast<int>(grad_.size()));
  const int x_begin = std::clamp(r.x_begin, 0, width), x_end = std::clamp(r.x_end, x_begin, width);
  // Grey rows are their own measure and are scanned in place.
  if (image.format == PixelFormat::mono8)
    return scan_row(image.row(r.y), x_begin, x_end, r, scan_row_index, min_contrast, to_8bit, out, count, capacity);
  if (image.format == PixelFormat::mono16)
    return scan_row(reinterpret_cast<const std::uint16_t*>(image.row(r.y)), x_begin, x_end, r, scan_row_index,
                    min_contrast, to_8bit, out, count, capacity);
  paint_measure_row(image, r.y, x_begin, x_end, measure_.data());
  return scan_row(measure_.data(), x_begin, x_end, r, scan_row_index, min_contrast, to_8bit, out, count, capacity);
}

// One piece on purpose (98 lines): it is detection's innermost loop, run over every pixel
// of every scan row; its prefix sums, box derivative, extremum flags and edge lists are
// local pointers into the members' storage that the compiler keeps in registers (the
// derivative and the flags one cloned vector pass, box_derivative_extrema), and
// tests/bench/detection_bench.cpp holds the whole to its budget.
template <typename Pixel>
int MarkScanner::scan_row(const Pixel* full_row, int x_begin, int x_end, const ScanRow& r, int scan_row_index,
                          float min_contrast, float to_8bit, MarkCandidate* out, int count, int capacity) {
  // Everything below is in the segment's own columns: row[0] is column x_begin.
  const Pixel* const row = full_row + x_begin;
  const int width = x_end - x_begin;
  std::int32_t* const P = prefix_.data();
  prefix_sums(row, width, P);

  // g[x]: sum of the h pixels right of the boundary x|x+1 minus the h pixels left of it.
  const int h = std::max(1, r.half_width);
  const int lo = h - 1, hi = width - 1 - h;  // boundaries with full boxes on both sides
  if (hi - lo < 3) return count;
  std::int32_t* const g = grad_.data();
  // An edge of contrast C gives a peak of C*h; half the minimum contrast finds the edges
  // of blurred or partly covered marks, the bar test below applies the full minimum.
  const auto edge_threshold = static_cast<std::int32_t>(std::ceil(0.5f * min_contrast * static_cast<float>(h)));
  int n_rising = 0, n_falling = 0;
  int rising_since_fall = -1, falling_since_rise = -1;
  Edge* rising = rising_.data();
  Edge* falling = falling_.data();
  // The extrema flagged in one vector pass, then the flags read eight at a time. A
  // textured row (concrete) has an extremum in nearly every 32-pixel block, but few per
  // eight pixels: searched pixel by pixel, its branches were a coin toss each.
  std::uint8_t* const flag = extrema_.data();
  box_derivative_extrema(P, h, lo, hi, edge_threshold, g, flag);
  std::memset(flag + hi, 0, kFlagWord);  // the last word's bytes past hi
  for (int word_start = lo + 1; word_start < hi; word_start += kFlagWord) {
    std::uint64_t word;
    std::memcpy(&word, flag + word_start, kFlagWord);
    while (word != 0) {
      const int k = std::countr_zero(word) / 8;
      const int x = word_start + k;
      word &= ~(std::uint64_t{0xff} << (8 * k));
      // Written to both lists, counted in one: which one is a coin toss on a textured
      // row, and a branch on it was mispredicted half the time. Each edge's partner is the
      // last edge of the other kind since the previous one of its own kind (a peak's
      // sub-pixel offset is under half a pixel: the positions' order is the pixels').
      const bool is_rising = flag[x] == 1;
      const std::int32_t sign = is_rising ? 1 : -1;
      const std::int32_t v = sign * g[x];
      const Edge e{static_cast<float>(x) + 0.5f + peak_offset(sign * g[x - 1], v, sign * g[x + 1]), v,
                   is_rising ? falling_since_rise : rising_since_fall};
      rising[n_rising] = e;
      falling[n_falling] = e;
      rising_since_fall = is_rising ? n_rising : -1;
      falling_since_rise = is_rising ? -1 : n_falling;
      n_rising += is_rising;
      n_falling += !is_rising;
    }
  }

  auto mean = [P, width](int a, int b) { return row_mean(P, width, a, b); };

  const int first_of_row = count;
  // Pair each falling edge with its partner, the last rising edge before it. Bars
  // narrower than paint are kept (flagged) down to a dot's lit cap when the row asks for
  // dots.
  const float min_width = std::min(r.min_width_px, r.min_dot_width_px);
  const int flank = std::max(2, static_cast<int>(std::lround(r.mark_px)));
  for (int fi = 0; fi < n_falling && count < capacity; ++fi) {
    const float b = falling[fi].x;
    const int last = falling[fi].partner;
    if (last < 0) continue;
    const float a = rising[last].x;
    const float w = b - a;
    if (w < min_width || w > r.max_width_px) continue;
    // Dark-bright-dark: the bar against each side, skipping the transition pixel. Edges
    // lie right of boundary lo + 1 > 0: truncation is their floor.
    const int ia = static_cast<int>(a), ib = static_cast<int>(b);
    const float inside = mean(ia + 1, ib);
    const float left = mean(ia - flank, ia - 1), right = mean(ib + 2, ib + 1 + flank);
    if (!(inside - left >= min_contrast) || !(inside - right >= min_contrast)) continue;
    // The box derivative places an edge where the row is flat for h pixels beyond it; a
    // second step within that reach (a shadow border, a patch, a dash's end) pulls the
    // peak towards it by up to h/2. Such a bar's centre is not where the paint is: the
    // detector drops it rather than hand the solver a biased pick, unless it is a dot
    // (a raised marker's own shadow is such a step, and a dot is narrower than the bias).
    // Contrast markings' black borders are such steps on both sides (between_black_borders).
    // Read at the edge and 1 and 2 pixels farther out: the frame's blur picks one.
    std::uint8_t step_beside_at = 0;
    for (int k = 0; k <= kMaxStepWindowOffset; ++k) {
      const int l = ia - k, rr = ib + k;
      const Flank beside_left{mean(l - h, l - 1), mean(l - 2 * h, l - h - 1)};
      const Flank beside_right{mean(rr + 2, rr + 1 + h), mean(rr + 2 + h, rr + 1 + 2 * h)};
      const bool steps = (beside_left.steps(inside) || beside_right.steps(inside)) &&
                         !between_black_borders(row, width, l - 1, rr + 2, beside_left, beside_right, inside,
                                                min_contrast, r.min_border_px, 4 * h);
      step_beside_at |= static_cast<std::uint8_t>(steps << k);
    }
    if (w >= kMinRampBarPx && inside - left >= 2.0f * min_contrast && inside - right >= 2.0f * min_contrast)
      add_edge_ramps(row, width, ia, ib, inside - left, inside - right);
    // The bar's own width: its area above the sides over its peak. Edge distance alone
    // cannot tell a thin bright line (a crack, a wire) from a mark, because the box
    // derivative spreads a thin line's edges to the box's width.
    const float background = 0.5f * (left + right);
    std::int64_t peak = 0;
    for (int x = std::max(ia, 0); x <= std::min(ib + 1, width - 1); ++x)
      peak = std::max<std::int64_t>(peak, static_cast<std::int64_t>(row[x]));
    const float area = static_cast<float>(P[std::min(ib + 2, width)] - P[std::max(ia, 0)]) -
                       background * static_cast<float>(std::min(ib + 2, width) - std::max(ia, 0));
    const float bar_width = area / (static_cast<float>(peak) - background);
    if (bar_width < min_width) continue;
    MarkCandidate& c = out[count++];
    c = MarkCandidate{};                                 // the slot may hold a candidate of an earlier scan
    c.left_px = static_cast<double>(a) + 1.0 + x_begin;  // to the picture's 1-based columns
    c.right_px = static_cast<double>(b) + 1.0 + x_begin;
    c.py = r.y + 1.0;
    c.contrast = static_cast<double>((inside - std::max(left, right)) * to_8bit);
    c.scan_row = static_cast<std::int16_t>(scan_row_index);
    c.step_beside_at = step_beside_at;
    c.step_beside = step_beside_at & 1;
    c.narrow = w < r.min_width_px || bar_width < r.min_width_px;
  }
  count =
      dots_.scan(row, P, x_begin, width, r, scan_row_index, min_contrast, to_8bit, out, first_of_row, count, capacity);
  return scan_joints(row, x_begin, width, r, scan_row_index, min_contrast, to_8bit, n_rising, out, first_of_row, count,
                     capacity);
}

template <typename Pixel>
int MarkScanner::scan_joints(const Pixel* row, int x_begin, int width, const ScanRow& r, int scan_row_index,
                             float min_contrast, float to_8bit, int n_rising, MarkCandidate* out, int first_of_row,
                             int count, int capacity) const {
  if (!(r.max_joint_px > 0.0f)) return count;
  const std::int32_t* const P = prefix_.data();
  const Edge* const rising = rising_.data();
  const Edge* const falling = falling_.data();
  auto mean = [P, width](int a, int b) { return row_mean(P, width, a, b); };
  // The box derivative spreads a line narrower than its box to the box's width: the
  // falling and the rising edge of a joint lie up to a box apart whatever its width.
  const int h = std::max(1, r.half_width);
  const float max_span = r.max_joint_px + static_cast<float>(h) + 1.0f;
  const int flank = std::max(2, static_cast<int>(std::lround(r.mark_px)));
  const int row_end = count;
  for (int ri = 0; ri < n_rising && count < capacity; ++ri) {
    const float b = rising[ri].x;
    const int last = rising[ri].partner;
    if (last < 0 || b - falling[last].x > max_span) continue;
    // A line's two edges are alike; a step's other edge (texture beside it) is not.
    const std::int32_t fall = falling[last].strength, rise = rising[ri].strength;
    if (2 * std::min(fall, rise) < std::max(fall, rise)) continue;
    const float a = falling[last].x;
    const int ia = static_cast<int>(a), ib = static_cast<int>(b);  // positive: their floor
    const float left = mean(ia - flank, ia - 1), right = mean(ib + 2, ib + 1 + flank);
    // The valley between: its darkest pixel first (integers), darker than both sides by
    // the minimum contrast, which agree to a fraction of it (a shadow's or a patch's
    // border is a step, not a line); only then its area below the sides and centroid.
    const int xa = std::max(ia, 0), xb = std::min(ib + 1, width - 1);
    Pixel darkest_px = row[xa];
    for (int x = xa + 1; x <= xb; ++x) darkest_px = std::min(darkest_px, row[x]);
    const auto darkest = static_cast<float>(darkest_px);
    const float background = 0.5f * (left + right), depth = background - darkest;
    if (!(std::min(left, right) - darkest >= min_contrast) || std::abs(left - right) > kJointSideMismatch * depth)
      continue;
    float area = 0.0f, moment = 0.0f;
    for (int x = xa; x <= xb; ++x) {
      const float below = std::max(0.0f, background - static_cast<float>(row[x]));
      area += below;
      moment += below * static_cast<float>(x);
    }
    const float joint_width = area / depth;
    if (joint_width > r.max_joint_px) continue;
    const float centre = moment / area;
    // A raised marker's own shadow (the dot pass's) is no joint.
    const double column = static_cast<double>(centre) + 1.0 + x_begin;  // 1-based
    bool shadow = false;
    for (int k = first_of_row; k < row_end && !shadow; ++k) {
      const MarkCandidate& d = out[k];
      const double edge = d.px(), far_end = edge + d.shadow_side * static_cast<double>(d.shadow_px);
      shadow = d.shadow_side != 0 && column >= std::min(edge, far_end) - 1.0 && column <= std::max(edge, far_end) + 1.0;
    }
    if (shadow) continue;
    MarkCandidate& c = out[count++];
    c = MarkCandidate{};
    c.left_px = column - 0.5 * static_cast<double>(joint_width);
    c.right_px = column + 0.5 * static_cast<double>(joint_width);
    c.py = r.y + 1.0;
    c.contrast = static_cast<double>(depth * to_8bit);
    c.scan_row = static_cast<std::int16_t>(scan_row_index);
    c.joint = true;
  }
  return count;
}

}  // namespace ccdlane
