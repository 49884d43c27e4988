// Pictures of pure noise, grey or colour, in several textures: frames in which no lane
// exists, for the estimator's "no lane in noise" tests and the tool that runs many.
#pragma once

#include <algorithm>
#include <cstdint>
#include <span>
#include <vector>

#include "base/image_view.hpp"

namespace ccdlane::test {

enum class NoiseTexture : std::uint8_t {
  uniform,          // every level equally likely
  gaussian,         // around a mid grey, of the given spread
  salt_and_pepper,  // a grey picture with a share of pixels black or white
  bright_blobs,     // bright discs and rectangles at random on a noisy grey
  bright_bars,      // bright thin bars, random length and direction, on a noisy grey
  // A night's or an underpass's: a dark grey (8-33) with sensor noise, faint bars 4-20
  // levels above it (where a dim road's lowered contrast threshold lets bars through,
  // contrast_threshold.hpp) and a few bright lamps. Not in kNoiseTextures: its own test.
  dark_bars,
};
inline constexpr NoiseTexture kNoiseTextures[] = {NoiseTexture::uniform, NoiseTexture::gaussian,
                                                  NoiseTexture::salt_and_pepper, NoiseTexture::bright_blobs,
                                                  NoiseTexture::bright_bars};

inline const char* to_string(NoiseTexture t) {
  switch (t) {
    case NoiseTexture::uniform: return "uniform";
    case NoiseTexture::gaussian: return "gaussian";
    case NoiseTexture::salt_and_pepper: return "salt_and_pepper";
    case NoiseTexture::bright_blobs: return "bright_blobs";
    case NoiseTexture::bright_bars: return "bright_bars";
    case NoiseTexture::dark_bars: return "dark_bars";
  }
  return "?";
}

// Draws noise frames of one size and format into its own buffer; fast enough to make
// thousands per test (one 64-bit xorshift draw gives 8 uniform or 2 Gaussian pixels).
class NoiseFrames {
 public:
  NoiseFrames(int width, int height, PixelFormat format, std::uint64_t seed)
      : width_(width),
        height_(height),
        channels_(format == PixelFormat::rgb8 ? 3 : 1),
        pixels_(static_cast<std::size_t>(width * height * channels_)),
        state_(seed * 0x9E3779B97F4A7C15ull + 1) {
    view_ = {pixels_.data(), width, height, width * channels_, format, 8};
  }

  // A new frame of `texture`; `level` 0..1 sets its strength (spread, share of salt,
  // number of blobs or bars).
  const ImageView& render(NoiseTexture texture, double level) {
    switch (texture) {
      case NoiseTexture::uniform: uniform(); break;
      case NoiseTexture::gaussian: gaussian(128.0, 4.0 + 60.0 * level); break;
      case NoiseTexture::salt_and_pepper: salt_and_pepper(0.01 + 0.3 * level); break;
      case NoiseTexture::bright_blobs:
        gaussian(90.0 + 40.0 * unit(), 3.0 + 10.0 * level);
        for (int i = 0, n = 5 + static_cast<int>(60 * level); i < n; ++i) blob();
        break;
      case NoiseTexture::bright_bars:
        gaussian(90.0 + 40.0 * unit(), 3.0 + 10.0 * level);
        for (int i = 0, n = 5 + static_cast<int>(60 * level); i < n; ++i) bar();
        break;
      case NoiseTexture::dark_bars: {
        const double dark = 8.0 + 25.0 * unit();
        gaussian(dark, 0.5 + 3.0 * level);
        for (int i = 0, n = 5 + static_cast<int>(60 * level); i < n; ++i) bar(dark + 4.0 + 16.0 * unit());
        for (int i = 0, n = 1 + below(4); i < n; ++i) blob();
        break;
      }
    }
    return view_;
  }

 private:
  std::uint64_t next() {
    std::uint64_t x = state_;
    x ^= x << 13;
    x ^= x >> 7;
    x ^= x << 17;
    return state_ = x;
  }
  double unit() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }
  int below(int n) { return static_cast<int>(unit() * n); }

  void uniform() {
    std::size_t i = 0;
    for (; i + 8 <= pixels_.size(); i += 8) {
      const std::uint64_t r = next();
      for (int b = 0; b < 8; ++b) pixels_[i + static_cast<std::size_t>(b)] = static_cast<std::uint8_t>(r >> (8 * b));
    }
    for (; i < pixels_.size(); ++i) pixels_[i] = static_cast<std::uint8_t>(next());
  }
  // Sum of four uniform bytes: mean 510, sigma 147.8 (Irwin-Hall), scaled to `sigma`.
  void gaussian(double mean, double sigma) {
    const double scale = sigma / 147.8;
    for (std::size_t i = 0; i < pixels_.size(); ++i) {
      const std::uint64_t r = (i & 1) == 0 ? next() : spare_;
      spare_ = r >> 32;
      const int sum = static_cast<int>((r & 255) + ((r >> 8) & 255) + ((r >> 16) & 255) + ((r >> 24) & 255));
      pixels_[i] = clamp_grey(mean + (sum - 510) * scale);
    }
  }
  void salt_and_pepper(double share) {
    gaussian(110.0, 3.0);
    const auto threshold = static_cast<std::uint64_t>(share * 65536.0);
    for (std::size_t i = 0; i < pixels_.size(); i += static_cast<std::size_t>(channels_)) {
      const std::uint64_t r = next();
      if ((r & 0xFFFF) >= threshold) continue;
      const std::uint8_t v = (r >> 16) & 1 ? 255 : 0;
      for (int c = 0; c < channels_; ++c) pixels_[i + static_cast<std::size_t>(c)] = v;
    }
  }
  // A bright disc or rectangle, 4..60 px across, of a random brightness and colour.
  void blob() {
    const int cx = below(width_), cy = below(height_), r = 2 + below(29);
    const bool disc = unit() < 0.5;
    const double grey = 150.0 + 105.0 * unit();
    for (int y = std::max(0, cy - r); y < std::min(height_, cy + r); ++y)
      for (int x = std::max(0, cx - r); x < std::min(width_, cx + r); ++x)
        if (!disc || (x - cx) * (x - cx) + (y - cy) * (y - cy) <= r * r) put(x, y, grey);
  }
  // A bright bar 2..12 px wide and 10..150 px long in any direction, of a random
  // brightness (or `grey`).
  void bar(double grey = -1.0) {
    const double x0 = unit() * width_, y0 = unit() * height_, angle = unit() * 3.14159265358979;
    const double length = 10.0 + 140.0 * unit(), half_width = 1.0 + 5.0 * unit();
    if (grey < 0.0) grey = 150.0 + 105.0 * unit();
    const double dx = std::cos(angle), dy = std::sin(angle);
    const int reach = static_cast<int>(length + half_width) + 1;
    for (int y = std::max(0, static_cast<int>(y0) - reach); y < std::min(height_, static_cast<int>(y0) + reach); ++y)
      for (int x = std::max(0, static_cast<int>(x0) - reach); x < std::min(width_, static_cast<int>(x0) + reach); ++x) {
        const double along = (x - x0) * dx + (y - y0) * dy, across = -(x - x0) * dy + (y - y0) * dx;
        if (along >= 0.0 && along <= length && std::abs(across) <= half_width) put(x, y, grey);
      }
  }
  void put(int x, int y, double grey) {
    const std::size_t i =
        (static_cast<std::size_t>(y) * static_cast<std::size_t>(width_) + static_cast<std::size_t>(x)) *
        static_cast<std::size_t>(channels_);
    for (int c = 0; c < channels_; ++c) pixels_[i + static_cast<std::size_t>(c)] = clamp_grey(grey);
  }
  static std::uint8_t clamp_grey(double v) { return static_cast<std::uint8_t>(std::clamp(v, 0.0, 255.0)); }

  int width_, height_, channels_;
  std::vector<std::uint8_t> pixels_;
  ImageView view_;
  std::uint64_t state_;
  std::uint64_t spare_ = 0;
};

}  // namespace ccdlane::test
