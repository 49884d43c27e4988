// The [synth] table: the synthetic road scene and the drive over it that `ccdlane synth`
// and the daemon's built-in demo render. Defaults give a plausible 3-lane highway.
#pragma once

#include <cstdint>

namespace ccdlane {

// Which lane lines are dashed: the inner ones (edges solid, the usual highway), all, none.
enum class DashedLines : std::uint8_t { inner, all, none };

// What the road is made of: dark asphalt, or light concrete (on which yellow paint has
// almost no contrast in grey).
enum class RoadSurface : std::uint8_t { asphalt, concrete };

inline constexpr int kMaxSynthCars = 6;  // [synth] cars at most

struct SynthConfig {
  // The sequence.
  std::uint64_t seed = 1;
  int frames = 100;         // frames a `ccdlane synth` run writes (--frames overrides)
  double rate_hz = 30.0;    // frame rate: t_ns = k / rate_hz
  double speed_mps = 25.0;  // how fast the dashes go by

  // The road (lengths in mm).
  int lanes = 3;     // 2..4 lanes (3..5 lines)
  int ego_lane = 1;  // 0 = leftmost lane
  double lane_width_mm = 3600.0;
  double line_width_mm = 120.0;       // inner lines
  double edge_line_width_mm = 150.0;  // the two outer lines
  DashedLines dashed = DashedLines::inner;
  double dash_length_mm = 3000.0;  // US interstate: 10 ft dashes,
  double dash_gap_mm = 9000.0;     //   30 ft gaps
  double curvature_per_mm = 0.0;   // c of y = y0 + c x^2 (1/(2R)); 0 = straight

  // The vehicle's motion within its lane.
  double weave_mm = 300.0;  // amplitude of the lateral weaving
  double weave_period_s = 6.0;
  double pitch_bump_deg = 0.4;  // amplitude of pitching over bumps
  double bump_period_s = 1.3;
  double roll_sway_deg = 0.3;  // amplitude of body roll
  double roll_period_s = 3.5;
  double lane_change_at_s = -1.0;  // start of a change to the lane on the right; < 0 = none
  double lane_change_s = 4.0;      // how long it takes

  // Appearance (grey levels on the 8-bit scale; 16-bit frames are scaled).
  double asphalt_grey = 95.0;
  double texture_grey = 10.0;  // amplitude of the asphalt texture
  double paint_grey = 200.0;
  double sky_grey = 185.0;
  double verge_grey = 70.0;   // beyond the shoulders
  double gradient = 0.2;      // brightness gradient across the picture (fraction)
  double shadow_depth = 0.3;  // darkening in shadows across the road; 0 = none
  double noise_sigma = 1.0;   // sensor noise, grey levels
  double blur_px = 0.0;       // Gaussian blur sigma, pixels; 0 = sharp
  int supersample = 4;        // sub-samples per pixel side at mark edges
  int bits = 8;               // 8: mono8 frames; 9..16: mono16 frames of that depth

  // Real-road disturbances. All off by default: the grey scene above is then unchanged.
  bool colour = false;               // rgb8 frames (bits must be 8); grey frames are the luma
  bool yellow_left_edge = false;     // the leftmost line is yellow paint (US: the median side)
  double yellow_paint_grey = 175.0;  // its luma
  RoadSurface surface = RoadSurface::asphalt;
  double concrete_grey = 170.0;  // the road's grey (luma) on concrete, instead of asphalt_grey
  bool hard_shadows = false;     // tree shadows: blobs with sharp borders across the road,
                                 //   darkening by shadow_depth, instead of soft bands
  bool barrier = false;          // a concrete barrier beside the left shoulder whose foot
                                 //   is bright (sunlit), a bar of light off the road plane
  bool road_markings = false;    // in the middle of every lane, every 50 m: a straight-ahead
                                 //   arrow (5 m, shaft 0.25 m wide) and 25 m on the word STOP
                                 //   (letters 2.5 m long, strokes 0.15 m): white paint of a
                                 //   lane mark's width running along the road
  bool crosswalks = false;       // every 80 m, a town's zebra crossing between the edge lines:
                                 //   bars 3 m along the road, 0.4 m wide, 0.6 m apart, and a
                                 //   stop line 0.5 m deep 2 m before them
  bool sealed_cracks = false;    // in every lane, 0.9 m right of its centre, a crack sealed
                                 //   along the road: two bands of black sealant 40 mm wide,
                                 //   150 mm apart, with the road's own surface between them
                                 //   (a strip a lane mark's width, brighter than its sides)
  double contrast_borders_mm = 0.0;  // black paint this wide along both sides of every line
                                     //   (contrast markings, laid on pale concrete); 0 = none
  int cars = 0;                      // 0..6 cars, each in the middle of a lane: the own lane's
                                     //   15-21 m ahead, the first on each side beside the car
                                     //   (3-9 m ahead), the rest 29-60 m: boxes 4.5 m long, 1.8 m
                                     //   wide, 1.5 m tall, a dark band along their bottom, a rear
                                     //   window and two tail lights (lit at night); they hide
                                     //   what lies behind them
  bool night = false;                // the road lit by the car's low beams alone: full to 8 m ahead,
                                     //   falling off as the square of the distance beyond, dimmer again
                                     //   past their cut-off (about 60 m) and off to the sides; the paint
                                     //   retroreflective (four times its daylight share of the light);
                                     //   no sky, haze or sun shadows. The levels above are the near
                                     //   road's; noise_sigma is the sensor's at the gain night asks

  // The gyro columns: the true roll and pitch (3DM-GX1 convention) plus noise.
  bool gyro = true;
  double gyro_noise_deg = 0.1;

  bool operator==(const SynthConfig&) const = default;
};

}  // namespace ccdlane
