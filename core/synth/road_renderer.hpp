// Renders a synthetic road frame through the exact camera model of docs/geometry.md: for each
// pixel, undistort, cast the ray to the road, and shade what it hits (asphalt or concrete
// texture, white and yellow lane paint, verge, soft or hard shadows, a barrier, sky), then
// blur and add sensor noise. Colour scenes give rgb8; grey frames are the scene's luma.
#pragma once

#include <array>
#include <vector>

#include "base/image_view.hpp"
#include "core/detection/ground_projector.hpp"
#include "core/geometry/camera_spec.hpp"
#include "core/synth/synth_config.hpp"
#include "core/synth/synth_drive.hpp"

namespace ccdlane {

class RoadRenderer {
 public:
  // Buffers for Nu x Nv are allocated here; render() allocates nothing.
  RoadRenderer(const CameraSpec& camera, const SynthConfig& scene);

  // Renders frame `truth` into `out` (Nu x Nv; mono8, or mono16 scaled to
  // out.significant_bits; rgb8 or bgr8 from a colour scene, the luma otherwise).
  // Deterministic for the scene's seed and truth.index.
  void render(const SynthFrame& truth, const MutableImageView& out);

  // The format frames of this scene have ([synth] colour, bits).
  PixelFormat format() const {
    return scene_.colour ? PixelFormat::rgb8 : scene_.bits > 8 ? PixelFormat::mono16 : PixelFormat::mono8;
  }

  // Linear light on the 8-bit scale, one value per channel.
  struct Rgb {
    double r, g, b;
  };

 private:
  struct Line {
    double y0, half_width, phase;
    bool dashed;
    Rgb paint;
  };

  // render()'s steps: the road of this frame (its lines, dashes and paint), the scene's
  // radiance seen through `v` into radiance_, and the sensor (noise, quantisation,
  // clipping) from radiance_ into `out`.
  void set_road(const SynthFrame& truth);
  void render_radiance(const GroundProjector& v);
  void expose(std::uint64_t frame_index, const MutableImageView& out);

  Rgb shade_ground(double X, double Y, double footprint) const;
  // [synth] sealed_cracks: the share of a pixel at (X, Y), fpY wide across the road, that
  // is crack sealant.
  double sealant_coverage(double X, double Y, double fpY) const;
  // How much of the pixel around (X, Y) (footprint fpX, fpY) is a line's paint, each line
  // widened by `widen_mm` on both sides (its contrast borders), and which line.
  double paint_coverage(const GroundProjector& v, double px, double py, double X, double Y, double fpX, double fpY,
                        int& line, double widen_mm = 0.0) const;
  bool paint_at(double X, double Y, double widen_mm = 0.0) const;
  // [synth] road_markings and crosswalks: how much of the pixel around (X, Y) (footprint
  // fpX, fpY) is an arrow's, a letter's or a crossing's paint, and whether the point
  // (X, Y) is.
  double marking_coverage(const GroundProjector& v, double px, double py, double X, double Y, double fpX,
                          double fpY) const;
  bool marking_at(double X, double Y, double reach) const;
  // The middle of the lane between lines j and j + 1, X ahead (the road's bend with it).
  double lane_centre_mm(int j, double X) const;
  // The share of n x n sub-samples of pixel (px, py) on the road for which inside(X, Y)
  // holds (n = [synth] supersample).
  template <typename Inside>
  double supersampled(const GroundProjector& v, double px, double py, Inside inside) const;
  Rgb sky(double qx, double qy, double qz) const;
  // [synth] night: the share of the near road's light the low beams give the road at
  // (X, Y) (ahead of and beside the camera); 1 by day.
  double headlights(double X, double Y) const;
  bool barrier_at(const Ray& lens, const Ray& q, double t_ground, Rgb& colour) const;
  // [synth] cars: whether the ray from `lens` along -q hits one of the cars ahead before
  // the ground (t_ground; 0: it never reaches the ground), and the colour it sees there.
  bool car_at(const Ray& lens, const Ray& q, double t_ground, Rgb& colour) const;
  void place_cars();  // this frame's cars_, after the road's lines (set_road)
  double shadow_at(double X, double Y, double sh_c, double sh_s, double shadow_offset) const;
  Rgb tinted(double grey, const Rgb& tint) const;
  void blur(float* radiance);  // one plane of radiance_

  CameraSpec camera_;
  SynthConfig scene_;
  int channels_ = 1;             // 3 for a colour scene
  std::vector<float> radiance_;  // linear levels (8-bit scale) before noise: the luma, or R, G, B planes
  std::vector<float> scratch_;   // blur pass
  std::vector<float> kernel_;    // Gaussian taps, one side
  std::vector<float> gauss_;     // a table of N(0,1) samples for sensor noise
  // Per-frame road state.
  Line lines_[kMaxRoadLines]{};
  int num_lines_ = 0;
  int ego_lane_ = 0;  // the lane the vehicle is in, 0 = leftmost
  // [synth] cars: where each stands (its rear, road x ahead; its middle, road y) and its
  // body's grey.
  struct Car {
    double rear = 0.0, middle = 0.0, body = 0.0;
  };
  std::array<Car, kMaxSynthCars> cars_{};
  int num_cars_ = 0;
  double c_ = 0.0, odometer_ = 0.0, period_ = 1.0;
  double road_left_ = 0.0, road_right_ = 0.0;  // asphalt edges (y0 of the edge lines + shoulder)
};

}  // namespace ccdlane
