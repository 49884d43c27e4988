// Shadowed dots along a row: each pixel against the road on both sides of it (prefix
// sums) gives runs of brighter and darker pixels; a bright run touching a dark one, each of a
// marker's size, is a candidate, kept when each stands out from the road on both sides of
// the pair by the minimum contrast, the two sides agree (not the border of a shadow or a
// patch), and the road there is smooth next to the contrast (not texture or noise).
#include "core/detection/dot_scanner.hpp"

#include <algorithm>
#include <cmath>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "core/detection/pixel_loop_clones.hpp"

namespace ccdlane {
namespace {

// A lit cap is the sunny half of the dome, a little more with blur; a shadow may be
// longer than the dome (a low sun) but not much longer.
constexpr float kMaxCapDots = 1.0f;
constexpr float kMinShadowDots = 0.3f;
constexpr float kMaxShadowDots = 3.0f;
constexpr float kBlurPx = 2.0f;
// Between cap and shadow, blur leaves a ramp that is neither: up to this much of a
// marker's width.
constexpr float kMaxGapDots = 0.5f;
// The two sides of the pair may differ by this fraction of its weaker contrast (a gentle
// shading of the road); a border between lit and shaded road differs by all of it.
constexpr float kSideMismatch = 0.5f;
// The road beside the pair: its mean absolute deviation at most this fraction of the
// pair's weaker contrast. A marker stands out from smooth road; noise and coarse texture
// make pairs of their own that do not. On TuSimple's concrete the road beside a marker
// deviates by a tenth of its contrast, up to a quarter where a seam runs along the
// markers (a fifth here loses a third of the markers found).
constexpr float kTextureShare = 0.3f;

// Each pixel of lo..hi-1 against the road on either side of it (see scan) into cls: +1
// lit, -1 shaded, 0 road. Branch-free; vectorised for the CPU's best target below.
template <typename Pixel>
inline void classify(const Pixel* __restrict row, const std::int32_t* __restrict P, int w, int lo, int hi,
                     std::int32_t threshold, std::int8_t* __restrict cls) {
  for (int x = lo; x < hi; ++x) {
    const std::int32_t road = std::max(P[x] - P[x - w], P[x + 1 + w] - P[x + 1]);
    const std::int32_t v = static_cast<std::int32_t>(row[x]) * w;
    cls[x] =
        static_cast<std::int8_t>(static_cast<int>(v - road >= threshold) - static_cast<int>(road - v >= threshold));
  }
}

CCDLANE_PIXEL_LOOP_CLONES
void classify_pixels(const std::uint8_t* row, const std::int32_t* P, int w, int lo, int hi, std::int32_t threshold,
                     std::int8_t* cls) {
  classify(row, P, w, lo, hi, threshold, cls);
}
CCDLANE_PIXEL_LOOP_CLONES
void classify_pixels(const std::uint16_t* row, const std::int32_t* P, int w, int lo, int hi, std::int32_t threshold,
                     std::int8_t* cls) {
  classify(row, P, w, lo, hi, threshold, cls);
}

}  // namespace

DotScanner::DotScanner(int max_width)
    : class_(static_cast<std::size_t>(max_width)), runs_(static_cast<std::size_t>(max_width)) {}

template <typename Pixel>
int DotScanner::scan(const Pixel* row, const std::int32_t* P, int x_begin, int width, const ScanRow& r, int scan_row,
                     float min_contrast, float to_8bit, MarkCandidate* out, int first_of_row, int count, int capacity) {
  const float dot = r.dot_px;
  if (!(dot > 0.0f)) return count;
  // Each pixel against the road on either side of it, a marker's width each: brighter
  // than both, or darker than the brighter, by the minimum contrast. The brighter side is
  // the road's: against one mean about a pixel, a marker's own shadow, darker and longer
  // than its cap, pulls the road's level down and the road beside the cap passes for lit;
  // and inside a shadow longer than a marker, one side is the shadow's own.
  const int w = std::max(2, static_cast<int>(std::lround(dot)));
  const auto threshold = static_cast<std::int32_t>(std::ceil(min_contrast * static_cast<float>(w)));
  // First every pixel's class, in a loop without branches the compiler vectorises (this
  // pass runs over every pixel of most scan rows); then the runs, from where it changes.
  std::int8_t* const cls = class_.data();
  const int lo = w, hi = width - w;
  classify_pixels(row, P, w, lo, hi, threshold, cls);
  int num_runs = 0;
  Run* runs = runs_.data();
  std::int8_t open = 0;
  const auto change = [&](int x) {  // the class changes at x
    if (open != 0) runs[num_runs - 1].end = x;
    open = cls[x];
    if (open != 0) runs[num_runs++] = {x, x, open};
  };
  if (lo < hi && cls[lo] != 0) change(lo);
  int next = lo + 1;
#if defined(__SSE2__)
  // Sixteen pixels at a time: a bit for each whose class differs from its left
  // neighbour's; changes are few on a road row, and only they are visited.
  for (; next + 16 <= hi; next += 16) {
    const __m128i here = _mm_loadu_si128(reinterpret_cast<const __m128i*>(cls + next));
    const __m128i left = _mm_loadu_si128(reinterpret_cast<const __m128i*>(cls + next - 1));
    auto changes = static_cast<unsigned>(~_mm_movemask_epi8(_mm_cmpeq_epi8(here, left))) & 0xFFFFu;
    for (; changes != 0; changes &= changes - 1) change(next + __builtin_ctz(changes));
  }
#endif
  for (; next < hi; ++next)
    if (cls[next] != cls[next - 1]) change(next);
  if (open != 0) runs[num_runs - 1].end = hi;

  auto mean = [P](int a, int b) {  // pixels [a, b)
    return static_cast<float>(P[b] - P[a]) / static_cast<float>(b - a);
  };
  const int flank = w;  // the road on either side of a pair, as of a pixel
  const int max_cap = static_cast<int>(kMaxCapDots * dot + kBlurPx);
  const int min_shadow = std::max(1, static_cast<int>(std::lround(kMinShadowDots * dot)));
  const int max_shadow = static_cast<int>(kMaxShadowDots * dot + kBlurPx);
  const int max_gap = std::max(1, static_cast<int>(std::lround(kMaxGapDots * dot)));
  const int row_end = count;
  for (int i = 0; i + 1 < num_runs && count < capacity; ++i) {
    const Run& first = runs[i];
    const Run& second = runs[i + 1];
    if (first.sign == second.sign || second.begin - first.end > max_gap) continue;
    const Run& cap = first.sign > 0 ? first : second;
    const Run& shadow = first.sign > 0 ? second : first;
    const int cap_w = cap.end - cap.begin, shadow_w = shadow.end - shadow.begin;
    if (cap_w > max_cap || shadow_w < min_shadow || shadow_w > max_shadow) continue;
    const int a = first.begin, b = second.end;
    if (a - 1 - flank < 0 || b + 1 + flank > width) continue;
    const float left = mean(a - 1 - flank, a - 1), right = mean(b + 1, b + 1 + flank);
    const float road = 0.5f * (left + right);
    const float cap_level = mean(cap.begin, cap.end), shadow_level = mean(shadow.begin, shadow.end);
    const float contrast = std::min(cap_level - road, road - shadow_level);
    if (!(contrast >= min_contrast) || std::abs(left - right) > kSideMismatch * contrast) continue;
    float deviation = 0.0f;
    for (int x = a - 1 - flank; x < a - 1; ++x) deviation += std::abs(static_cast<float>(row[x]) - left);
    for (int x = b + 1; x < b + 1 + flank; ++x) deviation += std::abs(static_cast<float>(row[x]) - right);
    if (deviation > kTextureShare * contrast * static_cast<float>(2 * flank)) continue;
    // The edge between cap and shadow, where the row crosses their middle level: the
    // dome's middle, the sun's side lit, the other dark.
    const float middle = 0.5f * (cap_level + shadow_level);
    const int sign = first.sign;  // +1: the cap first (its shadow to the right)
    float edge = -1.0f;
    for (int x = a; x + 1 < b && edge < 0.0f; ++x) {
      const float u = static_cast<float>(row[x]) - middle, v = static_cast<float>(row[x + 1]) - middle;
      if (static_cast<float>(sign) * u >= 0.0f && static_cast<float>(sign) * v < 0.0f)
        edge = static_cast<float>(x) + u / (u - v);
    }
    if (edge < 0.0f) continue;
    const double column = static_cast<double>(edge) + 1.0 + x_begin;  // 1-based
    bool known = false;                                               // the row filter's pass found the cap as a bar
    const double cap_centre = column - 0.5 * sign * cap_w;
    for (int k = first_of_row; k < row_end && !known; ++k)
      known = cap_centre >= out[k].left_px - 1.0 && cap_centre <= out[k].right_px + 1.0;
    if (known) continue;
    MarkCandidate& c = out[count++];
    c = MarkCandidate{};
    c.left_px = column - cap_w;
    c.right_px = column + cap_w;
    c.py = r.y + 1.0;
    c.contrast = static_cast<double>(contrast * to_8bit);
    c.scan_row = static_cast<std::int16_t>(scan_row);
    c.narrow = true;
    c.shadow_side = static_cast<std::int8_t>(sign);
    c.shadow_px = static_cast<float>(shadow_w);
    ++i;  // the second run is this pair's
  }
  return count;
}

template int DotScanner::scan(const std::uint8_t*, const std::int32_t*, int, int, const ScanRow&, int, float, float,
                              MarkCandidate*, int, int, int);
template int DotScanner::scan(const std::uint16_t*, const std::int32_t*, int, int, const ScanRow&, int, float, float,
                              MarkCandidate*, int, int, int);

}  // namespace ccdlane
