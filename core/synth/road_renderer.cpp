// The road renderer. Each pixel's ray is cast in closed form (GroundProjector); its
// derivatives give the pixel's footprint on the road, which decides where lane-mark edges
// need supersampling and how much asphalt texture survives the pixel's averaging.
#include "core/synth/road_renderer.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numbers>

#include "core/synth/random.hpp"

namespace ccdlane {
namespace {

constexpr double kShoulderMm = 700.0;       // asphalt beyond the edge lines
constexpr double kFineTextureMm = 90.0;     // asphalt grain
constexpr double kCoarseTextureMm = 700.0;  // patches, repairs
constexpr double kShadowPeriodMm = 23000.0;
constexpr double kShadowLengthMm = 5000.0;
constexpr double kShadowSoftMm = 500.0;
constexpr double kHazeStartMm = 80000.0;
constexpr double kHazeRangeMm = 300000.0;
constexpr int kGaussTable = 4096;
// Tree shadows: lattice noise at two scales, thresholded, so blobs of many sizes with
// sharp borders fall across the lane at all angles.
constexpr double kTreeShadowMm = 3000.0;
constexpr double kTreeDetailMm = 1100.0;
constexpr double kTreeShadowThreshold = 0.25;
// A concrete (Jersey) barrier: 810 mm high, its sunlit foot the lowest 250 mm.
constexpr double kBarrierHeightMm = 810.0;
constexpr double kBarrierFootMm = 250.0;
constexpr double kBarrierGrey = 135.0;
constexpr double kBarrierFootGrey = 220.0;

// A crack sealed along the road ([synth] sealed_cracks): two bands of sealant, the road's
// surface between them, set right of each lane's centre and wandering a little along it
// as a crack does.
constexpr double kSealantWidthMm = 40.0;
constexpr double kSealantApartMm = 150.0;  // centre to centre: 110 mm of road between
constexpr double kSealantFromCentreMm = -900.0;
constexpr double kSealantWanderMm = 80.0, kSealantWanderPeriodMm = 25000.0;
constexpr double kSealantGrey = 40.0;
// Contrast markings ([synth] contrast_borders_mm): black paint along both sides of each
// line, as some US states lay on pale concrete, where white paint alone shows little.
constexpr double kContrastBorderGrey = 30.0;

// Night ([synth] night): low beams light the road fully to kBeamFullMm ahead, then as the
// inverse square of the distance; beyond their cut-off (60 m for lamps 0.65 m up aimed
// 0.6 degrees down) only the beam's fringe reaches the road. Across, the beam spreads
// about 20 degrees either way, reaching farther to the right (right-hand traffic).
// Retroreflective paint sends the light back towards the lamps and the camera beside
// them: against asphalt it stands out far more than by day.
constexpr double kBeamFullMm = 8000.0;
constexpr double kBeamCutoffMm = 60000.0;
constexpr double kBeamBeyondCutoff = 0.15;
constexpr double kBeamSpreadRad = 0.35;
constexpr double kBeamRightRad = 0.035;
constexpr double kRetroreflection = 4.0;
constexpr double kNightSkyGrey = 4.0;

// Cars ahead ([synth] cars): boxes on the road in the middle of a lane, in the own lane,
// then the lanes left and right of it in turn. The first on either side is beside the
// car, its rear kCarBesideMm ahead (its side in full view, its body over the next line's
// near dashes), the others kCarFirstMm + k kCarApartMm ahead; each plus up to
// kCarJitterMm (seeded). Seen from behind: a dark band along the
// bottom (the underbody and its shadow), the body's grey, a darker rear window, two tail
// lights. The body's grey differs from car to car (dark to white).
constexpr double kCarLengthMm = 4500.0, kCarWidthMm = 1800.0, kCarHeightMm = 1500.0;
constexpr double kCarFirstMm = 15000.0, kCarApartMm = 7000.0, kCarJitterMm = 6000.0, kCarBesideMm = 3000.0;
constexpr double kCarUnderbodyMm = 350.0, kCarWindowMm = 1000.0;
constexpr double kTailLightBottomMm = 750.0, kTailLightTopMm = 950.0;
constexpr double kTailLightInnerMm = 550.0, kTailLightOuterMm = 850.0;  // from the car's middle
constexpr double kUnderbodyGrey = 18.0, kWindowGrey = 35.0, kTailLightGrey = 90.0, kLitTailLightGrey = 230.0;

using Rgb = RoadRenderer::Rgb;
Rgb operator+(const Rgb& a, const Rgb& b) { return {a.r + b.r, a.g + b.g, a.b + b.b}; }
Rgb operator-(const Rgb& a, const Rgb& b) { return {a.r - b.r, a.g - b.g, a.b - b.b}; }
Rgb operator*(double k, const Rgb& a) { return {k * a.r, k * a.g, k * a.b}; }

// Luma (Rec. 601) written so that a neutral colour's luma is its value exactly: grey
// scenes render bit for bit as they did before colour existed.
double luma(const Rgb& c) { return c.r + 0.587 * (c.g - c.r) + 0.114 * (c.b - c.r); }

// Hues as channel ratios scaled to luma 1, so that a surface's grey level is its luma.
Rgb hue(double r, double g, double b) {
  const double l = 0.299 * r + 0.587 * g + 0.114 * b;
  return {r / l, g / l, b / l};
}
const Rgb kNeutral{1.0, 1.0, 1.0};
const Rgb kYellowPaint = hue(1.0, 0.8, 0.25);  // road-marking yellow: its blue far below red and green
const Rgb kConcrete = hue(1.02, 1.0, 0.95);    // slightly warm
const Rgb kGrass = hue(0.85, 1.0, 0.7);
const Rgb kSky = hue(0.8, 0.92, 1.15);
const Rgb kTailLightRed = hue(2.4, 0.3, 0.3);

// Smooth lattice noise in [-1, 1] (bilinear between hashed lattice values).
double value_noise(double x, double y, std::uint64_t seed) {
  const double fx = std::floor(x), fy = std::floor(y);
  const auto ix = static_cast<std::int64_t>(fx), iy = static_cast<std::int64_t>(fy);
  double tx = x - fx, ty = y - fy;
  tx = tx * tx * (3.0 - 2.0 * tx);
  ty = ty * ty * (3.0 - 2.0 * ty);
  auto lattice = [seed](std::int64_t i, std::int64_t j) {
    const std::uint64_t h = synth::mix64(seed ^ (static_cast<std::uint64_t>(i) * 0x9E3779B97F4A7C15ull) ^
                                         (static_cast<std::uint64_t>(j) * 0xC2B2AE3D27D4EB4Full));
    return synth::unit(h) * 2.0 - 1.0;
  };
  const double a = lattice(ix, iy), b = lattice(ix + 1, iy), c = lattice(ix, iy + 1), d = lattice(ix + 1, iy + 1);
  return (a + (b - a) * tx) + ((c + (d - c) * tx) - (a + (b - a) * tx)) * ty;
}

double smoothstep(double e0, double e1, double x) {
  const double t = std::clamp((x - e0) / (e1 - e0), 0.0, 1.0);
  return t * t * (3.0 - 2.0 * t);
}

// Non-negative remainder.
double wrap(double x, double period) {
  const double r = std::fmod(x, period);
  return r < 0.0 ? r + period : r;
}

}  // namespace

RoadRenderer::RoadRenderer(const CameraSpec& camera, const SynthConfig& scene)
    : camera_(camera), scene_(scene), channels_(scene.colour ? 3 : 1) {
  const std::size_t n = static_cast<std::size_t>(camera.Nu) * static_cast<std::size_t>(camera.Nv);
  radiance_.assign(n * static_cast<std::size_t>(channels_), 0.0f);
  if (scene.blur_px > 0.0) {
    scratch_.assign(n, 0.0f);
    const int radius = static_cast<int>(std::ceil(3.0 * scene.blur_px));
    kernel_.resize(static_cast<std::size_t>(radius) + 1);
    std::vector<double> taps(kernel_.size());
    double sum = 0.0;
    for (int i = 0; i <= radius; ++i) {
      taps[static_cast<std::size_t>(i)] = std::exp(-0.5 * i * i / (scene.blur_px * scene.blur_px));
      sum += (i == 0 ? 1.0 : 2.0) * taps[static_cast<std::size_t>(i)];
    }
    for (std::size_t i = 0; i < taps.size(); ++i) kernel_[i] = static_cast<float>(taps[i] / sum);
  }
  // A table of normal samples, standardised so the noise has exactly the asked sigma.
  std::vector<double> g(kGaussTable);
  double mean = 0.0, var = 0.0;
  for (int i = 0; i < kGaussTable; ++i) {
    g[static_cast<std::size_t>(i)] = synth::normal(synth::hash(0x6A09E667F3BCC908ull, static_cast<std::uint64_t>(i)));
    mean += g[static_cast<std::size_t>(i)] / kGaussTable;
  }
  for (const double v : g) var += (v - mean) * (v - mean) / kGaussTable;
  gauss_.resize(kGaussTable);
  for (int i = 0; i < kGaussTable; ++i)
    gauss_[static_cast<std::size_t>(i)] = static_cast<float>((g[static_cast<std::size_t>(i)] - mean) / std::sqrt(var));
}

bool RoadRenderer::paint_at(double X, double Y, double widen_mm) const {
  const double bend = c_ * X * X;
  for (int j = 0; j < num_lines_; ++j) {
    const Line& l = lines_[j];
    if (std::abs(Y - l.y0 - bend) > l.half_width + widen_mm) continue;
    if (!l.dashed) return true;
    return wrap(X + odometer_ + l.phase, period_) < scene_.dash_length_mm;
  }
  return false;
}

namespace {

// Road markings in one lane's frame: u along the road from the marking's near end, v
// across from the lane's centre (+ left), mm.
constexpr double kMarkingPeriodMm = 50000.0;
constexpr double kWordStartMm = 25000.0;
constexpr double kLaneStaggerMm = 7000.0;  // each lane's markings this much further on than its left neighbour's
constexpr double kArrowLengthMm = 5000.0, kArrowShaftMm = 3500.0, kArrowShaftHalfMm = 125.0, kArrowHeadHalfMm = 450.0;
constexpr double kLetterMm = 2500.0, kLetterWidthMm = 600.0, kStrokeMm = 150.0, kLetterGapMm = 200.0;
constexpr double kWordHalfMm = 0.5 * (4 * kLetterWidthMm + 3 * kLetterGapMm);  // STOP, across the lane

// The capitals of STOP as strokes in a letter's box (a along the road, 0 near; b across
// from its left side), in units of the letter's length and width.
struct Stroke {
  double a0, a1, b0, b1;
};
constexpr double kT = kStrokeMm / kLetterMm, kW = kStrokeMm / kLetterWidthMm;
constexpr Stroke kS[] = {
    {1 - kT, 1, 0, 1}, {0.5 - kT / 2, 0.5 + kT / 2, 0, 1}, {0, kT, 0, 1}, {0.5, 1, 0, kW}, {0, 0.5, 1 - kW, 1}};
constexpr Stroke kTee[] = {{1 - kT, 1, 0, 1}, {0, 1, 0.5 - kW / 2, 0.5 + kW / 2}};
constexpr Stroke kO[] = {{1 - kT, 1, 0, 1}, {0, kT, 0, 1}, {0, 1, 0, kW}, {0, 1, 1 - kW, 1}};
constexpr Stroke kP[] = {{0, 1, 0, kW}, {1 - kT, 1, 0, 1}, {0.5 - kT / 2, 0.5 + kT / 2, 0, 1}, {0.5, 1, 1 - kW, 1}};
struct Letter {
  const Stroke* strokes;
  int count;
};
constexpr Letter kStop[] = {{kS, 5}, {kTee, 2}, {kO, 4}, {kP, 4}};

bool in_letter(const Letter& l, double a, double b) {
  for (int i = 0; i < l.count; ++i)
    if (a >= l.strokes[i].a0 && a <= l.strokes[i].a1 && b >= l.strokes[i].b0 && b <= l.strokes[i].b1) return true;
  return false;
}

// Whether (u, v) is paint; `reach` widens every shape (a footprint's test for edges).
bool marking_paint(double u, double v, double reach) {
  if (u < kArrowLengthMm + reach) {
    if (u < -reach) return false;
    if (u < kArrowShaftMm) return std::abs(v) <= kArrowShaftHalfMm + reach;
    return std::abs(v) <= kArrowHeadHalfMm * (kArrowLengthMm - u) / (kArrowLengthMm - kArrowShaftMm) + reach;
  }
  const double a = u - kWordStartMm;
  if (a < -reach || a > kLetterMm + reach) return false;
  const double b = kWordHalfMm - v;  // from the word's left side
  if (b < -reach || b > 2 * kWordHalfMm + reach) return false;
  if (reach > 0.0) return true;  // near the word: look closer
  const int i = static_cast<int>(b / (kLetterWidthMm + kLetterGapMm));
  const double in_box = b - i * (kLetterWidthMm + kLetterGapMm);
  if (i < 0 || i > 3 || in_box > kLetterWidthMm) return false;
  return in_letter(kStop[i], a / kLetterMm, in_box / kLetterWidthMm);
}

// A zebra crossing in the road's frame: u along the road from its stop line's near side,
// v across from the road's right edge line (+ left), the road w wide between its edge
// lines. Bars of a crossing run along the road, as lane lines do, a lane mark's length
// and three times its width: what a town's street shows beside its lines.
constexpr double kCrossingPeriodMm = 80000.0;
constexpr double kStopLineDepthMm = 500.0;
constexpr double kCrossingStartMm = 2500.0, kCrossingBarLengthMm = 3000.0;
constexpr double kCrossingBarWidthMm = 400.0, kCrossingBarPeriodMm = 1000.0;
constexpr double kCrossingFromEdgeMm = 300.0;  // the first bar's right side from the edge line

bool crossing_paint(double u, double v, double w, double reach) {
  if (v < -reach || v > w + reach) return false;
  if (u >= -reach && u <= kStopLineDepthMm + reach) return true;
  const double a = u - kCrossingStartMm;
  if (a < -reach || a > kCrossingBarLengthMm + reach) return false;
  if (reach > 0.0) return true;  // near the bars: look closer
  const double b = v - kCrossingFromEdgeMm;
  return b >= 0.0 && b <= w - 2 * kCrossingFromEdgeMm && wrap(b, kCrossingBarPeriodMm) <= kCrossingBarWidthMm;
}

}  // namespace

template <typename Inside>
double RoadRenderer::supersampled(const GroundProjector& v, double px, double py, Inside inside) const {
  const int n = scene_.supersample;
  int hits = 0, samples = 0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      double sx = 0.0, sy = 0.0;
      if (!v.ground(px + (j + 0.5) / n - 0.5, py + (i + 0.5) / n - 0.5, sx, sy)) continue;
      ++samples;
      hits += inside(sx, sy);
    }
  return samples ? static_cast<double>(hits) / samples : 0.0;
}

double RoadRenderer::lane_centre_mm(int j, double X) const {
  return 0.5 * (lines_[j].y0 + lines_[j + 1].y0) + c_ * X * X;
}

bool RoadRenderer::marking_at(double X, double Y, double reach) const {
  if (scene_.crosswalks && num_lines_ >= 2) {
    const double right = lines_[num_lines_ - 1].y0 + c_ * X * X, width = lines_[0].y0 - lines_[num_lines_ - 1].y0;
    const double u = wrap(X + odometer_, kCrossingPeriodMm);
    if (crossing_paint(u, Y - right, width, reach) || crossing_paint(u - kCrossingPeriodMm, Y - right, width, reach))
      return true;
  }
  if (!scene_.road_markings) return false;
  for (int j = 0; j + 1 < num_lines_; ++j) {
    const double centre = lane_centre_mm(j, X);
    if (std::abs(Y - centre) > std::max(kArrowHeadHalfMm, kWordHalfMm) + reach) continue;
    const double u = wrap(X + odometer_ + kLaneStaggerMm * j, kMarkingPeriodMm);
    if (marking_paint(u, Y - centre, reach) || marking_paint(u - kMarkingPeriodMm, Y - centre, reach)) return true;
  }
  return false;
}

double RoadRenderer::marking_coverage(const GroundProjector& v, double px, double py, double X, double Y, double fpX,
                                      double fpY) const {
  if (!marking_at(X, Y, fpX + fpY)) return 0.0;
  return supersampled(v, px, py, [this](double sx, double sy) { return marking_at(sx, sy, 0.0); });
}

double RoadRenderer::paint_coverage(const GroundProjector& v, double px, double py, double X, double Y, double fpX,
                                    double fpY, int& line, double widen_mm) const {
  // Only pixels whose footprint straddles a mark's side or a dash's end are
  // supersampled; the rest are inside or outside the paint as a whole.
  const double bend = c_ * X * X, slope = std::abs(2.0 * c_ * X);
  bool edge = false, inside = false;
  for (int j = 0; j < num_lines_ && !edge; ++j) {
    const Line& l = lines_[j];
    const double lateral = std::abs(Y - l.y0 - bend);
    const double reach = fpY + slope * fpX, half_width = l.half_width + widen_mm;
    if (lateral > half_width + reach) continue;
    line = j;
    if (lateral > half_width - reach) {
      edge = true;
      break;
    }
    if (!l.dashed) {
      inside = true;
      continue;
    }
    const double s = wrap(X + odometer_ + l.phase, period_);
    const double to_end = std::min({s, std::abs(s - scene_.dash_length_mm), period_ - s});
    if (to_end < fpX)
      edge = true;
    else
      inside = inside || s < scene_.dash_length_mm;
  }
  if (!edge) return inside ? 1.0 : 0.0;
  return supersampled(v, px, py, [this, widen_mm](double sx, double sy) { return paint_at(sx, sy, widen_mm); });
}

double RoadRenderer::sealant_coverage(double X, double Y, double fpY) const {
  // The share of the pixel's width across the road (fpY, at least a millimetre) on sealant.
  const double half = 0.5 * std::max(fpY, 1.0);
  const double wander = kSealantWanderMm * std::sin(2.0 * std::numbers::pi * (X + odometer_) / kSealantWanderPeriodMm);
  double covered = 0.0;
  for (int j = 0; j + 1 < num_lines_; ++j) {
    const double centre = lane_centre_mm(j, X) + kSealantFromCentreMm + wander;
    for (const double side : {-0.5, 0.5}) {
      const double c = centre + side * kSealantApartMm;
      covered +=
          std::max(0.0, std::min(Y + half, c + 0.5 * kSealantWidthMm) - std::max(Y - half, c - 0.5 * kSealantWidthMm));
    }
  }
  return std::min(1.0, covered / (2.0 * half));
}

double RoadRenderer::headlights(double X, double Y) const {
  if (!scene_.night) return 1.0;
  const double ahead = std::max(X, kBeamFullMm);
  const double falloff = (kBeamFullMm / ahead) * (kBeamFullMm / ahead);
  const double cut = 1.0 - (1.0 - kBeamBeyondCutoff) * smoothstep(0.8 * kBeamCutoffMm, 1.2 * kBeamCutoffMm, X);
  const double across = (std::atan2(Y, std::max(X, 1.0)) + kBeamRightRad) / kBeamSpreadRad;
  return falloff * cut * std::exp(-0.5 * across * across);
}

Rgb RoadRenderer::tinted(double grey, const Rgb& tint) const {
  return scene_.colour ? grey * tint : Rgb{grey, grey, grey};
}

Rgb RoadRenderer::shade_ground(double X, double Y, double footprint) const {
  const double bend = c_ * X * X;
  const bool road = Y - bend <= road_left_ && Y - bend >= road_right_;
  const std::uint64_t seed = scene_.seed;
  const double fine = std::min(1.0, kFineTextureMm / footprint), coarse = std::min(1.0, kCoarseTextureMm / footprint);
  const double sx = X + odometer_;  // texture is fixed to the road, the car moves over it
  double texture = 0.7 * fine * value_noise(sx / kFineTextureMm, Y / kFineTextureMm, seed) +
                   0.5 * coarse * value_noise(sx / kCoarseTextureMm, Y / kCoarseTextureMm, seed + 1);
  if (!road) return tinted(scene_.verge_grey + 2.0 * scene_.texture_grey * texture, kGrass);
  if (scene_.surface == RoadSurface::concrete)
    return tinted(scene_.concrete_grey + 0.5 * scene_.texture_grey * texture, kConcrete);
  return tinted(scene_.asphalt_grey + scene_.texture_grey * texture, kNeutral);
}

double RoadRenderer::shadow_at(double X, double Y, double sh_c, double sh_s, double shadow_offset) const {
  if (scene_.hard_shadows) {
    const double sx = X + odometer_;
    const double field = value_noise(sx / kTreeShadowMm, Y / kTreeShadowMm, scene_.seed + 71) +
                         0.5 * value_noise(sx / kTreeDetailMm, Y / kTreeDetailMm, scene_.seed + 72);
    return field > kTreeShadowThreshold ? 1.0 - scene_.shadow_depth : 1.0;
  }
  const double u = wrap((X + odometer_) * sh_c + Y * sh_s + shadow_offset, kShadowPeriodMm);
  const double in =
      smoothstep(0.0, kShadowSoftMm, u) * (1.0 - smoothstep(kShadowLengthMm, kShadowLengthMm + kShadowSoftMm, u));
  return 1.0 - scene_.shadow_depth * in;
}

// The barrier's face is the vertical surface over the left asphalt edge (following the
// road's bend); a ray hits it when it crosses that surface below the barrier's top before
// reaching the ground.
bool RoadRenderer::barrier_at(const Ray& lens, const Ray& q, double t_ground, Rgb& colour) const {
  if (!scene_.barrier || q.y >= 0.0) return false;  // the ray must head left (Y grows along -q)
  double t = (lens.y - road_left_) / q.y;
  for (int it = 0; it < 3; ++it) {
    const double X = lens.x - t * q.x;
    t = (lens.y - road_left_ - c_ * X * X) / q.y;
  }
  if (t <= 0.0 || (q.z > 0.0 && t >= t_ground)) return false;
  const double Z = lens.z - t * q.z;  // height above the road
  if (Z < 0.0 || Z > kBarrierHeightMm) return false;
  const double X = lens.x - t * q.x + odometer_;
  const double grain = scene_.texture_grey * value_noise(X / 400.0, Z / 400.0, scene_.seed + 81);
  colour = headlights(X - odometer_, lens.y - t * q.y) *
           tinted((Z < kBarrierFootMm ? kBarrierFootGrey : kBarrierGrey) + grain, kConcrete);
  return true;
}

void RoadRenderer::place_cars() {
  num_cars_ = 0;
  const int lanes = num_lines_ - 1;
  for (int k = 0; k < std::min(scene_.cars, kMaxSynthCars) && lanes > 0; ++k) {
    // The own lane, then one to the left, one to the right, two to the left, ...
    const int step = (k + 1) / 2, lane = ego_lane_ + (k % 2 == 1 ? -step : step);
    if (lane < 0 || lane >= lanes) continue;
    Car& car = cars_[static_cast<std::size_t>(num_cars_++)];
    car.rear = (k == 1 || k == 2 ? kCarBesideMm : kCarFirstMm + kCarApartMm * k) +
               kCarJitterMm * synth::unit(synth::hash(scene_.seed, 91, static_cast<std::uint64_t>(k)));
    car.middle = lane_centre_mm(lane, car.rear);
    car.body = 40.0 + 150.0 * synth::unit(synth::hash(scene_.seed, 92, static_cast<std::uint64_t>(k)));
  }
}

bool RoadRenderer::car_at(const Ray& lens, const Ray& q, double t_ground, Rgb& colour) const {
  bool hit = false;
  double nearest = 1e300;
  for (int k = 0; k < num_cars_; ++k) {
    const double rear = cars_[static_cast<std::size_t>(k)].rear, middle = cars_[static_cast<std::size_t>(k)].middle;
    // The box's slabs along the ray lens - t q: t where each coordinate is within them.
    const double lo[3] = {rear, middle - 0.5 * kCarWidthMm, 0.0};
    const double hi[3] = {rear + kCarLengthMm, middle + 0.5 * kCarWidthMm, kCarHeightMm};
    const double from[3] = {lens.x, lens.y, lens.z}, dir[3] = {q.x, q.y, q.z};
    double t_in = 0.0, t_out = 1e300;
    int face = -1;
    for (int a = 0; a < 3 && t_in <= t_out; ++a) {
      if (dir[a] == 0.0) {
        if (from[a] < lo[a] || from[a] > hi[a]) t_in = 1e300;
        continue;
      }
      double t1 = (from[a] - lo[a]) / dir[a], t2 = (from[a] - hi[a]) / dir[a];
      if (t1 > t2) std::swap(t1, t2);
      if (t1 > t_in) t_in = t1, face = a;
      t_out = std::min(t_out, t2);
    }
    if (t_in > t_out || t_in <= 0.0 || t_in >= nearest || (t_ground > 0.0 && t_in >= t_ground)) continue;
    nearest = t_in;
    hit = true;
    const double X = lens.x - t_in * q.x, Y = lens.y - t_in * q.y, Z = lens.z - t_in * q.z;
    const double body = cars_[static_cast<std::size_t>(k)].body;
    const double across = std::abs(Y - middle);
    if (face == 0 && Z >= kTailLightBottomMm && Z <= kTailLightTopMm && across >= kTailLightInnerMm &&
        across <= kTailLightOuterMm) {
      colour = tinted(scene_.night ? kLitTailLightGrey : kTailLightGrey, kTailLightRed);  // lit from within
      continue;
    }
    const double grey = Z < kCarUnderbodyMm             ? kUnderbodyGrey
                        : face == 0 && Z > kCarWindowMm ? kWindowGrey
                        : face == 1                     ? 0.8 * body
                        : face == 2                     ? 1.1 * body
                                                        : body;
    colour = headlights(X, Y) * tinted(grey, kNeutral);
  }
  return hit;
}

Rgb RoadRenderer::sky(double qx, double qy, double qz) const {
  if (scene_.night) return tinted(kNightSkyGrey, kSky);
  const double len = std::sqrt(qx * qx + qy * qy + qz * qz);
  const double elevation = -qz / len;  // of the ray going out into the scene, radians
  // A band of trees and posts on the horizon: vertical structure that is not road paint.
  const double azimuth = std::atan2(-qy, -qx);
  const auto bin = static_cast<std::int64_t>(std::floor(azimuth / 0.004));
  const std::uint64_t h = synth::hash(scene_.seed, 31, static_cast<std::uint64_t>(bin));
  const double height = 0.012 + 0.03 * synth::unit(h) * synth::unit(synth::mix64(h));
  if (elevation < height) return tinted(scene_.verge_grey * 0.8 + 45.0 * synth::unit(synth::mix64(h + 1)), kGrass);
  return tinted(scene_.sky_grey + 40.0 * std::min(elevation, 0.5), kSky);
}

void RoadRenderer::render(const SynthFrame& truth, const MutableImageView& out) {
  set_road(truth);
  render_radiance(GroundProjector(camera_, truth.pose));
  const std::size_t plane = static_cast<std::size_t>(camera_.Nu) * static_cast<std::size_t>(camera_.Nv);
  if (scene_.blur_px > 0.0)
    for (int c = 0; c < channels_; ++c) blur(radiance_.data() + static_cast<std::size_t>(c) * plane);
  expose(truth.index, out);
}

void RoadRenderer::set_road(const SynthFrame& truth) {
  num_lines_ = std::min(truth.num_lines, kMaxRoadLines);
  ego_lane_ = truth.ego_lane;
  c_ = truth.c_per_mm;
  odometer_ = truth.odometer_mm;
  period_ = scene_.dash_length_mm + scene_.dash_gap_mm;
  for (int j = 0; j < num_lines_; ++j) {
    const bool edge = j == 0 || j == num_lines_ - 1;
    lines_[j].y0 = truth.y0_mm[static_cast<std::size_t>(j)];
    lines_[j].half_width = 0.5 * (edge ? scene_.edge_line_width_mm : scene_.line_width_mm);
    lines_[j].dashed = scene_.dashed == DashedLines::all || (scene_.dashed == DashedLines::inner && !edge);
    lines_[j].phase = period_ * synth::unit(synth::hash(scene_.seed, 41, static_cast<std::uint64_t>(j)));
    lines_[j].paint = j == 0 && scene_.yellow_left_edge ? tinted(scene_.yellow_paint_grey, kYellowPaint)
                                                        : tinted(scene_.paint_grey, kNeutral);
  }
  road_left_ = lines_[0].y0 + kShoulderMm;
  road_right_ = lines_[num_lines_ - 1].y0 - kShoulderMm;
  place_cars();
}

void RoadRenderer::render_radiance(const GroundProjector& v) {
  const int W = camera_.Nu, H = camera_.Nv;
  const Ray &L = v.lens(), &T0 = v.t0(), &T1 = v.t1();
  const double pu = v.pitch_u(), pv = v.pitch_v(), cx = camera_.cx, cy = camera_.cy;
  const double corner2 = std::max(cx * cx, (W - cx) * (W - cx)) + std::max(cy * cy, (H - cy) * (H - cy));
  const double shadow_angle = 0.35 + 0.5 * synth::unit(synth::hash(scene_.seed, 51));
  const double sh_c = std::cos(shadow_angle), sh_s = std::sin(shadow_angle);
  const double shadow_offset = kShadowPeriodMm * synth::unit(synth::hash(scene_.seed, 52));
  const Rgb haze = tinted(scene_.sky_grey * 0.85, kSky);
  const std::size_t plane = static_cast<std::size_t>(W) * static_cast<std::size_t>(H);

  for (int y = 0; y < H; ++y) {
    float* dst = radiance_.data() + static_cast<std::size_t>(y) * static_cast<std::size_t>(W);
    const double py = y + 1.0;
    for (int x = 0; x < W; ++x) {
      const double px = x + 1.0;
      const double dx = px - cx, dy = py - cy;
      const double r2 = dx * dx + dy * dy;
      double s = 1.0;
      const Ray q = v.ray(px, py, &s);
      Rgb value;
      if (car_at(L, q, q.z > 0.0 ? L.z / q.z : 0.0, value)) {
        // A car ahead hides what lies behind it.
      } else if (barrier_at(L, q, q.z > 0.0 ? L.z / q.z : 0.0, value)) {
        // The barrier stands in the sun: the road's shadows are not cast on it.
      } else if (q.z <= 0.0) {
        value = sky(q.x, q.y, q.z);
      } else {
        const double inv_qz = 1.0 / q.z;
        const double t = L.z * inv_qz;
        const double X = L.x - t * q.x, Y = L.y - t * q.y;
        // Footprint: d(X, Y)/d(a, b) = -t (T_k - q T_kz / q_z), one pixel = (pu, pv).
        const double dXa = -t * (T0.x - q.x * T0.z * inv_qz) * pu * s;
        const double dYa = -t * (T0.y - q.y * T0.z * inv_qz) * pu * s;
        const double dXb = -t * (T1.x - q.x * T1.z * inv_qz) * pv * s;
        const double dYb = -t * (T1.y - q.y * T1.z * inv_qz) * pv * s;
        const double fpX = 0.5 * (std::abs(dXa) + std::abs(dXb)), fpY = 0.5 * (std::abs(dYa) + std::abs(dYb));
        const double footprint = 2.0 * std::sqrt(fpX * fpY) + 1e-9;
        value = shade_ground(X, Y, footprint);
        if (scene_.sealed_cracks)
          if (const double m = sealant_coverage(X, Y, fpY); m > 0.0)
            value = value + m * (tinted(kSealantGrey, kNeutral) - value);
        int line = 0;
        if (scene_.contrast_borders_mm > 0.0)
          if (const double m = paint_coverage(v, px, py, X, Y, fpX, fpY, line, scene_.contrast_borders_mm); m > 0.0)
            value = value + m * (tinted(kContrastBorderGrey, kNeutral) - value);
        const double retro = scene_.night ? kRetroreflection : 1.0;
        const double cover = paint_coverage(v, px, py, X, Y, fpX, fpY, line);
        if (cover > 0.0) value = value + cover * (retro * lines_[line].paint - value);
        if (scene_.road_markings || scene_.crosswalks)
          if (const double m = marking_coverage(v, px, py, X, Y, fpX, fpY); m > 0.0)
            value = value + m * (retro * tinted(scene_.paint_grey, kNeutral) - value);
        if (scene_.night) {
          value = headlights(X, Y) * value;
        } else {
          if (scene_.shadow_depth > 0.0) value = shadow_at(X, Y, sh_c, sh_s, shadow_offset) * value;
          if (X > kHazeStartMm) value = value + std::min(0.9, (X - kHazeStartMm) / kHazeRangeMm) * (haze - value);
        }
      }
      // Illumination falling off across the picture and towards its corners.
      value = (1.0 + scene_.gradient * (dx / W - 0.5 * r2 / corner2)) * value;
      if (channels_ == 1) {
        dst[x] = static_cast<float>(luma(value));
      } else {
        dst[x] = static_cast<float>(value.r);
        dst[plane + x] = static_cast<float>(value.g);
        dst[2 * plane + x] = static_cast<float>(value.b);
      }
    }
  }
}

void RoadRenderer::expose(std::uint64_t frame_index, const MutableImageView& out) {
  const int W = camera_.Nu, H = camera_.Nv;
  const std::size_t plane = static_cast<std::size_t>(W) * static_cast<std::size_t>(H);
  // Sensor: noise, quantisation, clipping.
  synth::PixelNoise noise(synth::hash(scene_.seed, 61, frame_index));
  const bool wide = out.format == PixelFormat::mono16;
  const int bits = wide ? std::clamp(out.significant_bits, 9, 16) : 8;
  const float maxval = static_cast<float>((1 << bits) - 1);
  const float scale = maxval / 255.0f;
  const float sigma = static_cast<float>(scene_.noise_sigma);
  if (is_colour(out.format)) {
    // Colour: each channel its own noise. A grey scene rendered into a colour frame is
    // neutral (its luma in every channel).
    const bool rgb = out.format == PixelFormat::rgb8;
    const std::size_t order[3] = {rgb ? 0u : 2u, 1u, rgb ? 2u : 0u};  // the plane of each byte
    for (int y = 0; y < H; ++y) {
      const std::size_t at = static_cast<std::size_t>(y) * static_cast<std::size_t>(W);
      std::uint8_t* row = out.row(y);
      for (int x = 0; x < W; ++x)
        for (std::size_t k = 0; k < 3; ++k) {
          const std::size_t c = channels_ == 3 ? order[k] : 0u;
          const float n = sigma > 0.0f ? sigma * gauss_[noise.next() >> 52] : 0.0f;
          const float value = radiance_[c * plane + at + static_cast<std::size_t>(x)] + n + 0.5f;
          row[3 * x + static_cast<int>(k)] = static_cast<std::uint8_t>(std::clamp(value, 0.0f, 255.0f));
        }
    }
    return;
  }
  // Grey frames of a colour scene are its luma.
  if (channels_ == 3)
    for (std::size_t i = 0; i < plane; ++i)
      radiance_[i] = static_cast<float>(luma({radiance_[i], radiance_[plane + i], radiance_[2 * plane + i]}));
  for (int y = 0; y < H; ++y) {
    const float* src = radiance_.data() + static_cast<std::size_t>(y) * static_cast<std::size_t>(W);
    std::uint8_t* row = out.row(y);
    for (int x = 0; x < W; ++x) {
      const float n = sigma > 0.0f ? sigma * gauss_[noise.next() >> 52] : 0.0f;
      const float value = std::clamp((src[x] + n) * scale + 0.5f, 0.0f, maxval);
      if (wide) {
        const auto v16 = static_cast<std::uint16_t>(value);
        std::memcpy(row + 2 * x, &v16, 2);
      } else {
        row[x] = static_cast<std::uint8_t>(value);
      }
    }
  }
}

void RoadRenderer::blur(float* radiance) {
  const int W = camera_.Nu, H = camera_.Nv, R = static_cast<int>(kernel_.size()) - 1;
  // Rows into scratch, then columns back into radiance, clamping at the borders.
  for (int y = 0; y < H; ++y) {
    const float* src = radiance + static_cast<std::size_t>(y) * static_cast<std::size_t>(W);
    float* dst = scratch_.data() + static_cast<std::size_t>(y) * static_cast<std::size_t>(W);
    for (int x = 0; x < W; ++x) {
      float sum = kernel_[0] * src[x];
      for (int i = 1; i <= R; ++i)
        sum += kernel_[static_cast<std::size_t>(i)] * (src[std::max(x - i, 0)] + src[std::min(x + i, W - 1)]);
      dst[x] = sum;
    }
  }
  for (int y = 0; y < H; ++y) {
    float* dst = radiance + static_cast<std::size_t>(y) * static_cast<std::size_t>(W);
    for (int x = 0; x < W; ++x) {
      float sum = kernel_[0] * scratch_[static_cast<std::size_t>(y * W + x)];
      for (int i = 1; i <= R; ++i)
        sum +=
            kernel_[static_cast<std::size_t>(i)] * (scratch_[static_cast<std::size_t>(std::max(y - i, 0) * W + x)] +
                                                    scratch_[static_cast<std::size_t>(std::min(y + i, H - 1) * W + x)]);
      dst[x] = sum;
    }
  }
}

}  // namespace ccdlane
